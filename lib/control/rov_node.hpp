// tiller-rov-control's logic: the ROV's pilot modes (control/rov_modes.hpp) and their 6-DOF
// per-axis controller (control/rov_axes.hpp). docs/flying.md, "ROV modes", is the user's view.
//
// Subscribes TILLER_MODE (the requested mode: teleop buttons, or a command such as
// `tiller-rov-control --mode depth_hold`), TILLER_MANUAL_DEMAND (the pilot's stick, [-1, 1]^6
// FRD), TILLER_ODOMETRY, TILLER_ALLOCATION_STATUS (the mixer's per-axis saturation: anti-windup)
// and TILLER_THRUSTER_COMMAND (the mixer's safety gate: control/integrator_gate.hpp). Every tick
// (rate_hz) it publishes TILLER_ARBITRATION (the mode in force and the source the mixer must
// allocate) and TILLER_WRENCH_ROV (wrench_t SOURCE_ROV_CONTROL, body FRD, N and N m).
// Modes and sources:
//   manual (MANUAL_OPEN_LOOP)  arbitration SOURCE_MANUAL_DEMAND: the mixer allocates the stick
//                              itself (seed 000's open loop, unchanged); the wrench is invalid
//   any assisted mode          arbitration SOURCE_ROV_CONTROL: the mixer allocates this wrench
// The thrust still leaves neutral only through the mixer's intent gate (lib/safety): these modes
// belong to the pilot (the stick must be centred after arming, the stick's loss is an input
// loss), and the wrench is invalid (so neutral, then the gate's disarm) while the pilot's demand
// or the odometry is stale or invalid (odometry_t.valid without ATTITUDE is not taken, counted
// in odometry.invalid; the modes that use the depth, control/rov_modes.hpp uses_depth, also
// need DEPTH, and position hold POSITION and VELOCITY; heading hold, stabilise and rate fly
// without a depth). A mode whose depth or position is not valid at the request is refused.
// Requests: a TILLER_MODE is acted on when it differs from the previous request (the teleop
// repeats its mode every second); a mode the layout cannot fly (the axes it needs are
// unactuated in the vehicle's effectiveness matrix, or position hold without a valid position)
// is refused: counted (mode.refused), the reason naming the axis in the heartbeat's
// status and the arbitration's reason, the mode in force kept.
// No thrust step on a switch: every switch blends the wrench in force (what the mixer achieved
// with the stick, coming from manual; the last published wrench otherwise) into the new mode's
// over blend_s. Going back to manual the output blends into what the mixer's open-loop
// allocation of the present stick achieves, then hands over to SOURCE_MANUAL_DEMAND.
// Position hold whose position goes invalid (fresh odometry without VALID_POSITION or
// VALID_VELOCITY, or a 1-sigma past position.max_std_m: the DVL's bottom lock lost, its driver
// stopped) falls back to position.on_loss (depth and heading hold by default: translations from
// the stick), blended like any switch, counted (position_hold.lost), said in the arbitration's
// reason and a DEGRADED heartbeat, and published on TILLER_MODE (source "rov-control") so the
// pilot's station shows it and repeats it: position hold resumes only when selected again.
// Waypointing (a mission: autonomy to the mixer's gate, no stick) flies TILLER_VELOCITY_SETPOINT
// (NED, into body u, v), the depth of TILLER_PATH along the TILLER_PATH_PROGRESS segment and the
// follower's heading, on references moved at half the axis' max_rate, then holds
// TILLER_STATION_TARGET; docs/flying.md "Missions at depth". A lost position falls back. Bad
// input is dropped and counted (rejected.<input>.<reason>). Pure: messages and time in; no clock;
// nothing allocates per tick.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "allocation/allocator.hpp"
#include "control/rov_axes.hpp"
#include "control/rov_config.hpp"
#include "control/rov_modes.hpp"
#include "runtime/node.hpp"
#include "safety/station_gate.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller::control {

class RovControlNode : public Node {
 public:
  RovControlNode(const RovControlParams& p, const Vehicle& vehicle);
  explicit RovControlNode(const RovControlParams& p);  // loads p.vehicle_file

  void on_mode(const controller_mode_t& m, TimeUs now);
  void on_manual(const manual_demand_t& m, TimeUs now);
  void on_arm_state(const arm_state_t& m, TimeUs now);
  void on_odometry(const odometry_t& m, TimeUs now);
  void on_allocation(const allocation_status_t& m, TimeUs now);
  void on_thruster_command(const thruster_command_t& m, TimeUs now);
  // Waypointing's guidance (tiller-path-follower's outputs and tiller-mission's path).
  void on_setpoint(const velocity_setpoint_t& m, TimeUs now);
  void on_station_target(const station_target_t& m, TimeUs now);
  void on_path(const path_t& m, TimeUs now);
  void on_progress(const path_progress_t& m, TimeUs now);
  void on_tick(TimeUs now) override;
  // Waypointing's references (m NED down, rad): what the depth and heading hold this tick.
  double depth_reference() const { return depth_ref_; }
  double heading_reference() const { return heading_ref_; }

  std::int8_t mode() const { return mode_; }  // in force
  bool leaving() const { return leaving_; }   // blending back into manual
  const std::string& reason() const { return reason_; }
  const RovAxes& axes() const { return axes_; }
  const std::array<bool, 6>& actuated() const { return actuated_; }
  const std::array<double, 6>& output() const { return last_out_; }
  const RovControlParams& params() const { return p_; }

 private:
  bool position_valid(TimeUs now);
  void switch_to(std::int8_t mode, const ModePlan& plan, TimeUs now);
  void fall_back(TimeUs now);
  void set_reason(const char* text);
  void publish(TimeUs now, std::int8_t source, bool valid);
  // Waypointing: the roles of X and Y and the stick that carries the setpoint this tick.
  void guide_roles(TimeUs now, std::array<AxisRole, 6>& roles, std::array<double, 6>& stick);
  // Waypointing: the depth and heading references (and the station's point) into the axes.
  void guide_targets(TimeUs now, double dt);
  double path_depth() const;  // the depth the path asks for where the vehicle is (m)

  RovControlParams p_;
  std::unique_ptr<Allocator> alloc_;
  std::string vehicle_name_;
  std::array<bool, 6> actuated_{};
  RovAxes axes_;
  ModePlan plan_;
  std::int8_t mode_;
  int requested_ = -1;                // the last TILLER_MODE acted on (-1: none yet)
  bool refused_waypointing_ = false;  // waypointing refused, retried on its repeats
  bool leaving_ = false;
  bool blending_ = false;
  TimeUs blend_start_ = 0;
  std::array<double, 6> from_{}, last_out_{};
  // Inputs.
  Freshness odom_fresh_, depth_fresh_, manual_fresh_, alloc_fresh_, cmd_fresh_;
  odometry_t odom_{};
  RovState state_;
  std::array<double, 6> stick_{};
  std::array<double, 6> achieved_{};
  std::array<bool, 6> reduced_{};
  std::int8_t alloc_source_ = wrench_t::SOURCE_NONE;
  std::int8_t gate_ = thruster_command_t::GATE_DISARMED;
  std::int8_t cmd_source_ = wrench_t::SOURCE_NONE;
  AllocationResult manual_result_;
  // Waypointing's guidance.
  Freshness setpoint_fresh_, station_fresh_, progress_fresh_;
  velocity_setpoint_t setpoint_{};
  station_target_t station_{};
  path_t path_{};
  path_progress_t progress_{};
  bool at_station_ = false;  // this tick holds the station target
  // The station's reference (m NED): from where the vehicle is when the target comes, moved
  // toward the target at half the surge max_rate (no full-gain step on the follower's 0.5 m).
  double station_ref_[2] = {0, 0};
  double depth_ref_ = 0, heading_ref_ = 0;
  std::int64_t *bad_setpoint_ = nullptr, *bad_station_ = nullptr, *bad_path_ = nullptr,
               *bad_progress_ = nullptr;
  // Outputs.
  wrench_t wrench_{};
  controller_mode_t mode_msg_{};
  std::int64_t* position_lost_ = nullptr;
  arbitration_t arb_{};
  std::string reason_, refusal_, status_;
  std::int64_t stale_seen_ = 0;
  safety::StationGate stations_;  // whose manual commands count (TILLER_ARM_STATE)
  std::int64_t* rejected_station_ = nullptr;
  std::int64_t *nan_odometry_, *range_odometry_, *invalid_odometry_, *bad_manual_, *bad_mode_,
      *unavailable_, *bad_allocation_, *bad_command_, *switches_;
};

}  // namespace tiller::control
