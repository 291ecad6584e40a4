// tiller-station-keep's logic: the last-meter station-keeping PID as a node.
//
// Subscribes TILLER_ODOMETRY, TILLER_STATION_TARGET, TILLER_ARBITRATION, TILLER_ALLOCATION_STATUS
// and TILLER_THRUSTER_COMMAND (the mixer's safety gate: control/integrator_gate.hpp). Every tick
// (rate_hz) it publishes TILLER_WRENCH_STATION (body FRD [X Y 0 0 0 N], N and N m; invalid while
// there is no fresh active target) and its terms on TILLER_PID_STATION. It integrates only while
// the arbitration makes it the active source and the mixer's gate is ACTIVE with this wrench
// allocated (reset to zero while disarmed or waiting for a start, frozen otherwise:
// control/integrator_gate.hpp). The integrator restarts from zero on entry; its output is blended
// from the velocity PID's last wrench over blend_s, so the hand-over has no thrust step. A target
// without a heading holds the heading the vehicle has when the target first becomes active. In
// control without a fresh active target (the arbiter's hold: a path cancelled, aborted or paused,
// the guidance stale) it holds where the vehicle is: the position and heading when it took control,
// re-captured while the mixer's gate says disarmed or waiting for a start (so a start holds where
// the vehicle is then). Odometry stale: neutral (an invalid wrench: the mixer's input lost, then
// its disarm after safety.disarm_after_s), or the last wrench for hold_s, per config; stale
// because the estimator keeps flagging the odometry invalid: a valid zero wrench (armed; resumes,
// ramped over blend_s, when valid) for odometry_invalid_neutral_s (control/estimate_watch.hpp).
// Bad input (core/message_checks.hpp) is dropped and counted: odometry with non-finite values
// (rejected.odometry.nan) or angles / covariance size out of contract (rejected.odometry.range);
// an active target with NaN, a position beyond 1e6 m or a valid heading outside (-pi, pi]
// (rejected.target.invalid); an arbitration with an unknown mode or source
// (rejected.arbitration.invalid); an allocation status out of contract
// (rejected.allocation.invalid); a velocity-PID wrench with NaN (rejected.wrench_velocity.nan); a
// thruster command out of contract (rejected.thruster_command.invalid).
#pragma once

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/wrench_t.hpp>

#include "control/blend.hpp"
#include "control/control_config.hpp"
#include "control/estimate_watch.hpp"
#include "control/station_pid.hpp"
#include "runtime/node.hpp"

namespace tiller::control {

class StationKeepNode : public Node {
 public:
  explicit StationKeepNode(const StationKeepNodeParams& p);

  void on_odometry(const odometry_t& m, TimeUs now);
  void on_target(const station_target_t& m, TimeUs now);
  void on_arbitration(const arbitration_t& m, TimeUs now);
  void on_allocation(const allocation_status_t& m, TimeUs now);
  void on_velocity_wrench(const wrench_t& m, TimeUs now);
  void on_thruster_command(const thruster_command_t& m, TimeUs now);
  void on_tick(TimeUs now) override;

  const PidTerms& terms() const { return terms_; }
  bool active() const { return active_; }
  // Holding where the vehicle was, with no target (the arbiter's hold).
  bool holding_here() const { return hold_here_valid_; }

 private:
  // A counter made on first use (a rejection), so good input leaves the heartbeat as it was.
  std::int64_t& first_use(std::int64_t*& c, const char* name);
  void publish_wrench(TimeUs now, bool valid, double x, double y, double n);

  StationKeepNodeParams p_;
  StationPid pid_;
  PidTerms terms_;
  odometry_t odom_{};
  station_target_t target_{};
  arbitration_t arb_{};
  allocation_status_t alloc_{};
  Freshness odom_fresh_, target_fresh_, arb_fresh_, alloc_fresh_;
  std::int64_t seen_stale_ = 0;
  bool active_ = false;
  bool hold_heading_valid_ = false;
  double hold_heading_ = 0;
  bool hold_here_valid_ = false;  // holding where the vehicle was (no target): that pose
  double hold_n_ = 0, hold_e_ = 0, hold_psi_ = 0;
  TimeUs last_odom_utime_ = -1;
  wrench_t last_wrench_{};
  wrench_t velocity_wrench_{};
  Freshness velocity_fresh_;
  Freshness command_fresh_;  // TILLER_THRUSTER_COMMAND: the mixer's gate and source
  std::int8_t command_gate_ = thruster_command_t::GATE_DISARMED;
  std::int8_t command_source_ = wrench_t::SOURCE_NONE;
  Blend blend_;
  bool was_active_ = false;
  std::int64_t *nan_odometry_, *bad_target_, *bad_velocity_wrench_;
  bool odom_invalid_ = false;     // the last odometry lacked position, velocity or attitude
  EstimateWatch estimate_;        // the estimator flags a needed part invalid: deliberate neutral
  bool invalid_neutral_ = false;  // gave that neutral at the previous tick
  std::int64_t* invalid_odometry_ = nullptr;                             // made on first use
  std::int64_t *range_odometry_ = nullptr, *bad_arbitration_ = nullptr,  // made on first use
                                               *bad_allocation_ = nullptr,
               *range_velocity_wrench_ = nullptr, *bad_command_ = nullptr;
};

}  // namespace tiller::control
