#include "control/arbiter.hpp"

#include <tiller/controller_mode_t.hpp>
#include <tiller/wrench_t.hpp>

namespace tiller::control {

ArbiterDecision Arbiter::decide(const ArbiterInput& in) {
  ArbiterDecision d;
  d.mode = in.mode;
  switch (in.mode) {
    case controller_mode_t::MANUAL_OPEN_LOOP:
      d.source = wrench_t::SOURCE_MANUAL_DEMAND;
      d.reason = "manual open loop: demand straight to the mixer";
      break;
    case controller_mode_t::MANUAL_CLOSED_LOOP:
      d.source = wrench_t::SOURCE_VELOCITY_PID;
      d.reason = "manual closed loop: velocity PID on the manual command";
      break;
    case controller_mode_t::WAYPOINTING:
      if (!in.progress_fresh || !in.path_active) {
        d.source = wrench_t::SOURCE_NONE;
        d.reason = "waypointing: no path (neutral)";
      } else if (in.complete && (in.distance_to_goal <= p_.station_radius ||
                                 (last_source_ == wrench_t::SOURCE_STATION_KEEP &&
                                  in.distance_to_goal <= p_.station_radius + p_.hysteresis))) {
        d.source = wrench_t::SOURCE_STATION_KEEP;
        d.reason = "waypointing: path complete, near the goal: station keeping";
      } else {
        d.source = wrench_t::SOURCE_VELOCITY_PID;
        d.reason = in.complete ? "waypointing: path complete, returning to the goal"
                               : "waypointing: following the path";
      }
      break;
    default:
      d.source = wrench_t::SOURCE_NONE;
      d.reason = "unknown mode (neutral)";
  }
  d.changed = d.source != last_source_;
  last_source_ = d.source;
  return d;
}

}  // namespace tiller::control
