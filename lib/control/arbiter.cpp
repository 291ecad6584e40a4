#include "control/arbiter.hpp"

#include <tiller/controller_mode_t.hpp>
#include <tiller/wrench_t.hpp>

namespace tiller::control {

ArbiterDecision Arbiter::decide(const ArbiterInput& in) {
  ArbiterDecision d;
  d.mode = in.mode;
  if (in.mode != controller_mode_t::WAYPOINTING) had_path_ = false;
  if (in.failsafe_hold) {
    if (in.mode == controller_mode_t::WAYPOINTING && in.progress_fresh && in.path_active)
      had_path_ = true;
    d.source = p_.hold_position ? wrench_t::SOURCE_STATION_KEEP : wrench_t::SOURCE_NONE;
    d.reason = p_.hold_position ? "failsafe: holding position (TILLER_VEHICLE_STATUS)"
                                : "failsafe: hold asked, this vehicle cannot hold: neutral";
    d.changed = d.source != last_source_ || d.reason != last_reason_;
    last_source_ = d.source;
    last_reason_ = d.reason;
    return d;
  }
  switch (in.mode) {
    case controller_mode_t::MANUAL_OPEN_LOOP:
      d.source = wrench_t::SOURCE_MANUAL_DEMAND;
      d.reason = "manual open loop: demand straight to the mixer";
      break;
    case controller_mode_t::MANUAL_CLOSED_LOOP:
      d.source = wrench_t::SOURCE_VELOCITY_PID;
      d.reason = "manual closed loop: velocity PID on the manual command";
      break;
    case controller_mode_t::WAYPOINTING: {
      const bool following = in.progress_fresh && in.path_active;
      if (following) had_path_ = true;
      if (following && in.setpoint_fresh) {
        if (in.complete && (in.distance_to_goal <= p_.station_radius ||
                            (last_source_ == wrench_t::SOURCE_STATION_KEEP &&
                             in.distance_to_goal <= p_.station_radius + p_.hysteresis))) {
          d.source = wrench_t::SOURCE_STATION_KEEP;
          d.reason = "waypointing: path complete, near the goal: station keeping";
        } else {
          d.source = wrench_t::SOURCE_VELOCITY_PID;
          d.reason = in.complete ? "waypointing: path complete, returning to the goal"
                                 : "waypointing: following the path";
        }
      } else if (had_path_) {
        // Hold: the path stopped (progress fresh, no active segment) or the guidance is lost.
        const bool stopped = in.progress_fresh && !in.path_active;
        d.source = p_.hold_position ? wrench_t::SOURCE_STATION_KEEP : wrench_t::SOURCE_NONE;
        d.reason = stopped
                       ? (p_.hold_position
                              ? "waypointing: path stopped (cancel, abort, pause): holding position"
                              : "waypointing: path stopped: neutral (this vehicle cannot hold)")
                       : (p_.hold_position
                              ? "waypointing: guidance lost (progress or setpoint stale): holding"
                              : "waypointing: guidance lost: neutral (this vehicle cannot hold)");
      } else {
        d.source = wrench_t::SOURCE_NONE;
        d.reason = "waypointing: no path (neutral)";
      }
      break;
    }
    case controller_mode_t::STABILISE:
    case controller_mode_t::DEPTH_HOLD:
    case controller_mode_t::HEADING_HOLD:
    case controller_mode_t::RATE:
    case controller_mode_t::SURFACE:
    case controller_mode_t::POSITION_HOLD:
    case controller_mode_t::DEPTH_HEADING_HOLD:
      d.source = wrench_t::SOURCE_NONE;
      d.reason = "an ROV mode (tiller-rov-control), not for this vehicle: neutral";
      break;
    default:
      d.source = wrench_t::SOURCE_NONE;
      d.reason = "unknown mode (neutral)";
  }
  d.changed = d.source != last_source_ || d.reason != last_reason_;
  last_source_ = d.source;
  last_reason_ = d.reason;
  return d;
}

}  // namespace tiller::control
