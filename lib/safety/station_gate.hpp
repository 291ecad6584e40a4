// safety::StationGate: whose manual commands count (docs/safety.md, "One station in control").
//
// tiller-esc names the station in control in TILLER_ARM_STATE (arm_state_t.controller): the
// station whose arm request armed the vehicle, or that took control since with a takeover
// request. A node that takes manual commands (manual_demand_t, manual_velocity_cmd_t: the mixer,
// tiller-rov-control, tiller-velocity-pid) feeds it every accepted arm state and asks allows()
// for each command's station: a command from another station is refused and counted
// (rejected.<input>.station), so two stations holding the same key cannot both steer.
// No controller named (disarmed, or armed by a request that named no station, e.g. a mission
// runner): every station's commands count, as before stations existed. Pure, no clock.
#pragma once

#include <string>

#include <tiller/arm_state_t.hpp>

namespace tiller::safety {

class StationGate {
 public:
  void on_arm_state(const arm_state_t& a) {
    const std::string& c = a.armed ? a.controller : kNone;
    if (c != controller_) controller_ = c;  // assign only on change: no allocation per message
  }
  bool allows(const std::string& station) const {
    return controller_.empty() || station == controller_;
  }
  const std::string& controller() const { return controller_; }

 private:
  inline static const std::string kNone;
  std::string controller_;
};

}  // namespace tiller::safety
