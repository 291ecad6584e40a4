// tiller-failsafe's config (config/failsafe/<vehicle>.yaml), strict: an unknown, missing,
// mistyped or out-of-range key stops the program with the file, the line, the key and what was
// expected (core/config.hpp). A rule's section present = that rule on; absent = off. Keys and
// their meaning: docs/reference/configuration.md ("Failsafes").
#pragma once

#include <string>

#include "failsafe/monitor.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::failsafe {

struct FailsafeNodeParams {
  double rate_hz = 10;  // status, failsafe wrench and heartbeat rate
  MonitorParams monitor;
  // The failsafe wrench's up-force (N, body FRD -Z) for SURFACE and RISE. The default, 1e5 N,
  // is beyond any vehicle's thrusters: the mixer's saturation then gives the most up-thrust the
  // vertical thrusters make (full up-thrust) in the direction asked.
  double surface_thrust_n = 1e5;
  double rise_thrust_n = 1e5;
};

FailsafeNodeParams load_failsafe_params(const config::Value& root);
FailsafeNodeParams load_failsafe_file(const std::string& path);

}  // namespace tiller::failsafe
