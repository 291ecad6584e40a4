// Loaders for the controllers' YAML (config/control/<vehicle>.yaml), the seed's pidgains.yaml
// made strict. One file holds three sections: `velocity_pid:` and `arbiter:` (read by
// tiller-velocity-pid) and `station_keep:` (read by tiller-station-keep); each program marks the
// other's section as used. Gains are absolute (N per m/s, N per m, ...), not the seed's
// multipliers of baked-in gains.
#pragma once

#include <cstdint>
#include <string>

#include "control/arbiter.hpp"
#include "control/station_pid.hpp"
#include "control/velocity_pid.hpp"
#include "core/config.hpp"

namespace tiller::control {

// What a controller does when its odometry stops (older than odometry_timeout_s).
enum class StaleAction {
  kNeutral,  // zero wrench at once
  kHold,     // keep the last wrench (integrators frozen) for hold_s more, then zero
};

struct ControllerNodeCommon {
  double rate_hz = 20;
  double odometry_timeout_s = 0.5;
  StaleAction on_stale = StaleAction::kNeutral;
  double hold_s = 0.5;
  double input_timeout_s = 0.5;       // setpoints, targets, progress, manual commands
  double allocation_timeout_s = 0.5;  // TILLER_ALLOCATION_STATUS older than this is ignored
  double blend_s = 1.0;  // s: on taking over, blend from the other controller's last wrench
  // s: while the estimator keeps flagging a needed part of the odometry invalid (a GNSS outage
  // past its limit), a valid zero wrench (neutral, still armed; resumes when valid) for at most
  // this long since it went invalid; 0: an invalid wrench at once (the mixer's disarm follows).
  // lib/control/estimate_watch.hpp.
  double invalid_neutral_s = 60.0;
};

struct VelocityPidNodeParams {
  ControllerNodeCommon common;
  VelocityPidParams pid;
  ArbiterParams arbiter;
};

struct StationKeepNodeParams {
  ControllerNodeCommon common;
  StationPidParams pid;
};

AxisGains load_axis_gains(const config::Value& v);
// The Munk model's numbers from a vehicle file's surface_3dof dynamics: m11, m22, m23 of its
// coriolis_mass_matrix (else mass_matrix), y_v of linear_damping; fraction 1.
MunkModel vehicle_munk_model(const std::string& vehicle_file);
VelocityPidParams load_velocity_pid_params(const config::Value& v);
StationPidParams load_station_pid_params(const config::Value& v);
ArbiterParams load_arbiter_params(const config::Value& v);
std::int8_t parse_mode(const config::Value& v, const char* key);

// From the whole file; marks the other program's section used.
VelocityPidNodeParams load_velocity_pid_node_params(const config::Value& root);
StationKeepNodeParams load_station_keep_node_params(const config::Value& root);

}  // namespace tiller::control
