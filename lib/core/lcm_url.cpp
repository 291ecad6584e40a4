#include "core/lcm_url.hpp"

#include <cctype>

namespace tiller {

namespace {

// The value of `key` in the URL's query ("udpm://addr:port?key=value&..."), or nullptr.
bool query_value(const std::string& url, const std::string& key, std::string& out) {
  const auto q = url.find('?');
  if (q == std::string::npos) return false;
  std::size_t i = q + 1;
  while (i <= url.size()) {
    std::size_t end = url.find('&', i);
    if (end == std::string::npos) end = url.size();
    const std::string item = url.substr(i, end - i);
    const auto eq = item.find('=');
    if (item.substr(0, eq) == key) {
      out = eq == std::string::npos ? "" : item.substr(eq + 1);
      return true;
    }
    i = end + 1;
  }
  return false;
}

}  // namespace

int lcm_url_ttl(const std::string& url) {
  std::string v;
  if (!query_value(url, "ttl", v)) return 0;
  if (v.empty() || v.size() > 3) return -1;
  for (char c : v)
    if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
  return std::stoi(v);
}

std::string lcm_url_problem(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return "";
  const int ttl = lcm_url_ttl(url);
  if (ttl >= 0 && ttl <= kMaxLcmTtl) return "";
  std::string v;
  query_value(url, "ttl", v);
  return "a udpm:// URL with ttl=0 (this computer only) or ttl=1 (topside and vehicle "
         "computers on one link), got ttl=" +
         v;
}

}  // namespace tiller
