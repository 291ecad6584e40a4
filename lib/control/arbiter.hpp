// The controller choice of seed 004 (choose_pid_node), in one place. Hosted by
// tiller-velocity-pid, published on TILLER_ARBITRATION; the mixer follows it.
//
// Rules (mode from TILLER_MODE, progress from TILLER_PATH_PROGRESS):
//   MANUAL_OPEN_LOOP   -> SOURCE_MANUAL_DEMAND (teleop's demand straight to the mixer)
//   MANUAL_CLOSED_LOOP -> SOURCE_VELOCITY_PID  (the velocity PID tracks TILLER_MANUAL_VELOCITY)
//   WAYPOINTING        -> SOURCE_VELOCITY_PID while the path is not complete or the vehicle is
//                         farther than station_radius (m) from the goal; SOURCE_STATION_KEEP
//                         once it is complete and within station_radius. Back to the velocity
//                         PID only beyond station_radius + hysteresis (no chatter at the edge).
//                         No path yet in this mode (fresh progress without one, or none) ->
//                         SOURCE_NONE (neutral).
//                         HOLD, once a path was followed in this mode (docs/safety.md): the path
//                         stopped (cancelled, aborted, paused: progress without an active
//                         segment) or the guidance lost (progress or setpoint stale) ->
//                         SOURCE_STATION_KEEP, which holds where the vehicle is (or the
//                         follower's target); with hold_position false (a vehicle that cannot
//                         hold) -> SOURCE_NONE (neutral; the mixer disarms after its limit).
// The ROV modes (STABILISE .. POSITION_HOLD, decided by tiller-rov-control) -> SOURCE_NONE.
// Before any TILLER_MODE arrives, default_mode applies. A mode stays in force until changed;
// leaving WAYPOINTING forgets the path (back in it, no path means neutral again).
// Pure logic: decide() takes the inputs and the time and returns the decision.
#pragma once

#include <cstdint>
#include <string>

namespace tiller::control {

struct ArbiterParams {
  std::int8_t default_mode = 0;  // controller_mode_t constant
  double station_radius = 2.0;   // m: switch to station keeping within this of the goal
  double hysteresis = 0.5;       // m: leave station keeping beyond radius + this
  bool hold_position = true;     // the vehicle can hold position (tiller-station-keep runs)
};

struct ArbiterInput {
  std::int8_t mode = 0;         // controller_mode_t constant in force
  bool progress_fresh = false;  // TILLER_PATH_PROGRESS fresh
  bool path_active = false;     // the follower has a path and an active segment (not paused)
  bool setpoint_fresh = true;   // TILLER_VELOCITY_SETPOINT fresh
  bool complete = false;
  double distance_to_goal = 0;  // m
};

struct ArbiterDecision {
  std::int8_t mode = 0;
  std::int8_t source = 0;   // wrench_t SOURCE_* constant
  const char* reason = "";  // static string
  bool changed = false;     // source or reason differs from the previous decision
};

class Arbiter {
 public:
  // No reason string is longer than this (test/control): the nodes size their strings to it at
  // construction, so a mode change allocates nothing.
  static constexpr std::size_t kMaxReasonLength = 80;

  explicit Arbiter(const ArbiterParams& p = {}) : p_(p) {}
  ArbiterDecision decide(const ArbiterInput& in);
  std::int8_t source() const { return last_source_; }
  const ArbiterParams& params() const { return p_; }

 private:
  ArbiterParams p_;
  std::int8_t last_source_ = -1;
  const char* last_reason_ = nullptr;
  bool had_path_ = false;  // a path was followed since WAYPOINTING came into force
};

}  // namespace tiller::control
