// Parameters of tiller-rov-control (plain struct) and their strict loader: the `rov_control:`
// section of config/control/<vehicle>.yaml (docs/reference/configuration.md). Units SI: m, s,
// rad, N, N m.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <tiller/controller_mode_t.hpp>

#include "control/rov_axes.hpp"
#include "core/config.hpp"

namespace tiller::control {

struct RovControlParams {
  std::string vehicle_file;           // resolved path of the vehicle description (its thrusters)
  double rate_hz = 50;                // control and publishing rate
  double odometry_timeout_s = 0.5;    // older odometry: the wrench is invalid (neutral)
  double input_timeout_s = 0.5;       // the pilot's TILLER_MANUAL_DEMAND
  double allocation_timeout_s = 0.5;  // the mixer's thruster command and allocation status
  double blend_s = 1.0;               // every switch blends the wrench in force into the new one
  std::int8_t default_mode = 0;       // controller_mode_t constant before any TILLER_MODE
  bool require_position_covariance = true;  // odometry without a covariance has no position
  double max_position_std_m = 0.5;  // position valid while its horizontal 1-sigma is below this
  // Where position hold goes when its position is lost (position.on_loss; the DVL's bottom lock
  // lost, its driver stopped): depth and heading held, translations from the stick, by default.
  // It does not come back by itself: the pilot selects position hold again.
  std::int8_t position_loss_mode = controller_mode_t::DEPTH_HEADING_HOLD;
  double surface_speed_m_s = 0.25;  // SURFACE rises at this
  double surface_depth_m = 0.15;    // and leaves heave alone above this depth
  std::array<RovGains, 6> axes{};   // [X Y Z K M N] = surge sway heave roll pitch yaw
};

// Reads the `rov_control:` section of `root`. `vehicle:` is resolved like the mixer's (beside
// the file, then its parent folders, then the current directory). Throws config::Error naming
// the file, the key and what was expected.
RovControlParams load_rov_control(const config::Value& root);
RovControlParams load_rov_control_file(const std::string& path);

}  // namespace tiller::control
