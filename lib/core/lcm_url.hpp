// The LCM URL rule, one function for every place a URL comes from (a launch file's lcm_url, any
// program's --lcm-url, LCM_DEFAULT_URL): a udpm:// URL may carry ttl=0 (the default: packets
// never leave this computer) or ttl=1 (one hop: the topside and vehicle computers on one
// network segment, docs/real-vehicle.md). A larger TTL would let routers forward the traffic
// (multicast TTL, RFC 1112 section 6.1) and is refused. Other URL schemes (memq://, file://)
// carry no TTL and are left alone.
#pragma once

#include <string>

namespace tiller {

inline constexpr int kMaxLcmTtl = 1;

// "" when `url` is acceptable, else what was expected (for a config error or an option error),
// e.g. "a udpm:// URL with ttl=0 (this computer) or ttl=1 (two computers on one link), got
// ttl=2".
std::string lcm_url_problem(const std::string& url);

// The TTL a udpm:// URL asks for (0 when it names none); -1 if the value is not a number.
int lcm_url_ttl(const std::string& url);

}  // namespace tiller
