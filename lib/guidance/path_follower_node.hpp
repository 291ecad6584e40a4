// tiller-path-follower's logic: the seed-004 command-velocity generator as a node.
//
// Subscribes TILLER_PATH (path_t: a new path_id restarts the follower, 0 points cancels),
// TILLER_ODOMETRY (pose NED, heading), TILLER_MODE (is_translation) and TILLER_MISSION_COMMAND
// (the operator's PAUSE, RESUME, ABORT, RELEASE; a repeated command_id is ignored) and
// TILLER_PATH_SPEED (path_speed_t: segment k of that path_id at min(speed[k], max_speed); a bad
// one is dropped and counted, rejected.path_speed.invalid):
//   PAUSE    stop following, keep the path (progress: its path_id, segment -1; setpoint inactive):
//            the arbiter holds position (station keeping where the vehicle is);
//   RESUME   follow the paused path again, from where the vehicle is;
//   ABORT, RELEASE, and a cancel (0 points)  drop the path; repeats of the dropped path_id
//            (tiller-mission sends its path every second) are ignored, a new path_id starts.
// It listens to TILLER_PID_VELOCITY too, and with follower.surge_integral_drag > 0 uses it
// (pid_terms_t of controller "velocity"): at a steady surge speed (setpoint and measurement within
// kSteadySurgeError, the integrator not frozen) the surge integral over that drag, negated, is the
// current along the heading (m/s), handed to PathFollower::observe_current_along with the latest
// odometry's heading: the part of the current along a leg that the cross-track law cannot see.
// At rate_hz it publishes
//   TILLER_VELOCITY_SETPOINT  velocity [north east 0] m/s (FRAME_NED) and target heading rad;
//                             inactive when there is no path or the odometry is stale;
//   TILLER_PATH_PROGRESS      segment, cross-track / along-track m, distance to goal m, complete;
//   TILLER_STATION_TARGET     the last point (and its heading) once the path is complete.
// A GNSS outage (the odometry's DEAD_RECKONING): for outage_hold_course_s from its start the
// setpoint is the one from before it, course and speed held rather than steered by a drifting
// estimate (counted in outages; the heartbeat says so, DEGRADED); then the path is followed on
// the estimate until tiller-failsafe's GNSS rule holds or stops the vehicle.
// Bad input: a path with NaN, out-of-range or too many points is dropped whole and counted
// (rejected.path.invalid); odometry that fails its contract (core/message_checks.hpp) is dropped
// and counted: non-finite values under rejected.odometry.nan, angles out of range or a
// covariance of the wrong size under rejected.odometry.range; a mode message with an unknown
// mode is dropped and counted (rejected.mode.invalid).
#pragma once

#include <array>

#include <tiller/controller_mode_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/pid_terms_t.hpp>

#include "guidance/follower_config.hpp"
#include "guidance/path_follower.hpp"
#include "runtime/node.hpp"

namespace tiller::guidance {

class PathFollowerNode : public Node {
 public:
  explicit PathFollowerNode(const FollowerNodeParams& p);

  void on_path(const path_t& m, TimeUs now);
  void on_odometry(const odometry_t& m, TimeUs now);
  void on_mode(const controller_mode_t& m, TimeUs now);
  void on_command(const mission_command_t& m, TimeUs now);
  void on_speed(const path_speed_t& m, TimeUs now);
  void on_pid(const pid_terms_t& m, TimeUs now);
  static constexpr double kSteadySurgeError = 0.02;  // m/s
  void on_tick(TimeUs now) override;

  const PathFollower& follower() const { return follower_; }
  const FollowerOutput& last_output() const { return out_; }
  // In a GNSS outage's first outage_hold_course_s: the setpoint is the one from before it.
  bool holding_course(TimeUs now) const;
  bool paused() const { return paused_; }

 private:
  void start_pending_path();
  void drop_path();

  FollowerNodeParams p_;
  PathFollower follower_;
  FollowerOutput out_;
  Freshness odom_fresh_;
  std::int64_t seen_stale_ = 0;
  Vec2 pos_{0, 0};
  double heading_ = 0;
  TimeUs odom_time_ = 0;
  bool dead_reckoning_ = false;  // the latest odometry says DEAD_RECKONING
  TimeUs dr_since_ = -1;         // when this outage began (-1: none)
  FollowerOutput held_;          // the setpoint held through the outage's first seconds
  std::int64_t* outages_ = nullptr;
  TimeUs last_update_odom_time_ = -1;
  bool is_translation_ = false;
  std::int64_t path_id_ = -1;
  std::array<std::int64_t, 8> dropped_ids_;  // the last cancelled or aborted path ids
  std::size_t next_dropped_slot_ = 0;
  bool paused_ = false;
  std::array<std::int64_t, 8> seen_commands_{};  // the last command ids acted on
  std::size_t next_command_slot_ = 0;
  bool pending_ = false;
  std::vector<Waypoint> pending_points_;
  std::int64_t* nan_odometry_;
  std::int64_t* range_odometry_ = nullptr;    // made on first use
  std::int64_t* invalid_odometry_ = nullptr;  // made on first use
  std::int64_t* bad_mode_ = nullptr;          // made on first use
  std::int64_t* bad_pid_ = nullptr;           // made on first use
  std::int64_t* bad_command_ = nullptr;       // made on first use
  std::int64_t* dropped_repeats_ = nullptr;   // made on first use
  std::int64_t* invalid_path_;
  int last_segment_ = 0;               // the follower's segment at its last update
  path_speed_t speeds_{};              // the latest speeds (path_id -1: none)
  std::int64_t* bad_speed_ = nullptr;  // made on first use
  std::int64_t* paths_started_;
};

}  // namespace tiller::guidance
