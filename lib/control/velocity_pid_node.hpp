// tiller-velocity-pid's logic: the arbiter (seed 004's choose_pid) and the velocity PID.
//
// Subscribes TILLER_ODOMETRY, TILLER_VELOCITY_SETPOINT (waypointing), TILLER_MANUAL_VELOCITY
// (manual closed loop), TILLER_MODE, TILLER_PATH_PROGRESS, TILLER_ALLOCATION_STATUS and
// TILLER_THRUSTER_COMMAND (the mixer's safety gate: control/integrator_gate.hpp). Every
// tick (rate_hz) it decides the wrench source and publishes TILLER_ARBITRATION, then publishes
// TILLER_WRENCH_VELOCITY (body FRD [X Y 0 0 0 N], N and N m) and its terms on
// TILLER_PID_VELOCITY. The PID integrates only while it is the active source (its integrator
// restarts from zero on entry, and its output is blended over blend_s from the wrench in force
// before: the station keeper's last wrench, or what the mixer achieved with the pilot's
// open-loop stick, so the hand-over has no thrust step), with dt from the odometry times, frozen
// while the mixer reports the axis reduced, and only while the mixer's gate is ACTIVE with this
// PID's wrench allocated (reset to zero while disarmed or waiting for a start, frozen otherwise:
// control/integrator_gate.hpp). A mode switch while it stays the source (manual
// closed loop <-> waypointing, both VELOCITY_PID) is a hand-over too: integrators reset to
// zero, blend from the last published wrench, dt = 0 on that tick. No fresh setpoint: wrench
// invalid (the mixer treats it as absent). Odometry stale: neutral (an invalid wrench: the mixer's
// input lost, then its disarm after safety.disarm_after_s), or the last wrench for hold_s, per
// config; stale because the estimator keeps flagging the odometry invalid: a valid zero wrench
// (armed; resumes, ramped over blend_s, when valid) for odometry_invalid_neutral_s
// (control/estimate_watch.hpp). The arbiter's hold (path stopped, guidance stale, tiller-failsafe's
// HOLD on TILLER_VEHICLE_STATUS: the last one received stays in force) hands over to station
// keeping. Bad input (core/message_checks.hpp) is dropped and counted: odometry with non-finite
// values (rejected.odometry.nan) or angles / covariance size out of contract
// (rejected.odometry.range); a setpoint out of contract, e.g. a valid heading outside (-pi, pi]
// (rejected.setpoint.invalid); an allocation status out of contract (rejected.allocation.invalid);
// a manual command, mode or path progress out of contract (rejected.manual/mode/progress.invalid);
// a station-keep wrench with NaN (rejected.wrench_station.nan); a thruster command out of contract
// (rejected.thruster_command.invalid).
#pragma once

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "control/arbiter.hpp"
#include "control/blend.hpp"
#include "control/control_config.hpp"
#include "control/estimate_watch.hpp"
#include "control/velocity_pid.hpp"
#include "runtime/node.hpp"
#include "safety/station_gate.hpp"

namespace tiller::control {

class VelocityPidNode : public Node {
 public:
  explicit VelocityPidNode(const VelocityPidNodeParams& p);

  void on_odometry(const odometry_t& m, TimeUs now);
  void on_setpoint(const velocity_setpoint_t& m, TimeUs now);
  void on_manual(const manual_velocity_cmd_t& m, TimeUs now);
  void on_arm_state(const arm_state_t& m, TimeUs now);
  void on_mode(const controller_mode_t& m, TimeUs now);
  void on_progress(const path_progress_t& m, TimeUs now);
  void on_allocation(const allocation_status_t& m, TimeUs now);
  void on_station_wrench(const wrench_t& m, TimeUs now);
  void on_thruster_command(const thruster_command_t& m, TimeUs now);
  void on_vehicle_status(const vehicle_status_t& m, TimeUs now);
  void on_tick(TimeUs now) override;

  const ArbiterDecision& decision() const { return decision_; }
  const PidTerms& terms() const { return terms_; }

 private:
  // A counter made on first use (a rejection), so good input leaves the heartbeat as it was.
  std::int64_t& first_use(std::int64_t*& c, const char* name);
  void publish_wrench(TimeUs now, bool valid, double x, double y, double n);

  VelocityPidNodeParams p_;
  VelocityPid pid_;
  Arbiter arbiter_;
  ArbiterDecision decision_;
  PidTerms terms_;
  odometry_t odom_{};
  velocity_setpoint_t setpoint_{};
  manual_velocity_cmd_t manual_{};
  path_progress_t progress_{};
  allocation_status_t alloc_{};
  Freshness odom_fresh_, setpoint_fresh_, manual_fresh_, progress_fresh_, alloc_fresh_;
  std::int64_t seen_stale_ = 0;
  std::int8_t mode_;
  bool is_translation_ = false;
  TimeUs last_odom_utime_ = -1;
  wrench_t last_wrench_{};
  arbitration_t arb_{};
  std::string reason_;
  wrench_t station_wrench_{};
  Freshness station_fresh_;
  Freshness command_fresh_;  // TILLER_THRUSTER_COMMAND: the mixer's gate and source
  std::int8_t command_gate_ = thruster_command_t::GATE_DISARMED;
  std::int8_t command_source_ = wrench_t::SOURCE_NONE;
  bool failsafe_hold_ = false;  // tiller-failsafe's last action was HOLD (or RETURN)
  Blend blend_;
  bool was_active_ = false;
  std::int8_t prev_source_ = -1;  // the arbiter's source at the previous tick
  std::int8_t prev_mode_ = -1;    // the arbiter's mode at the previous tick
  safety::StationGate stations_;  // whose manual commands count (TILLER_ARM_STATE)
  std::int64_t* rejected_station_ = nullptr;
  std::int64_t *nan_odometry_, *bad_setpoint_, *bad_manual_, *bad_progress_, *bad_mode_,
      *bad_station_wrench_;
  bool odom_invalid_ = false;     // the last odometry lacked velocity or attitude
  EstimateWatch estimate_;        // the estimator flags a needed part invalid: deliberate neutral
  bool invalid_neutral_ = false;  // gave that neutral at the previous tick
  std::int64_t* invalid_odometry_ = nullptr;                            // made on first use
  std::int64_t *range_odometry_ = nullptr, *bad_allocation_ = nullptr,  // made on first use
                                               *range_station_wrench_ = nullptr,
               *bad_command_ = nullptr, *bad_status_ = nullptr;
};

}  // namespace tiller::control
