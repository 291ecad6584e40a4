// Loads the path follower's parameters (FollowerParams, see path_follower.hpp) from the
// `follower:` section of a guidance YAML file (config/guidance/*.yaml). Strict: every key is
// required, ranges are checked, angles only under keys ending in _deg.
#pragma once

#include <string>

#include "core/config.hpp"
#include "guidance/path_follower.hpp"

namespace tiller::guidance {

// braking_decel is a number (m/s^2), or derived from the vehicle's braking ability:
//   braking_decel: {vehicle_file: config/vehicles/otter.yaml, fraction: 0.16}
// = fraction * (reverse thrust along the surge axis, summed over the thrusters) / m11 (the
// surge mass with added mass, from the file's dynamics section). Drag is left out (it helps
// more the faster the boat goes), and `fraction` is the margin: the seed's notes advise a
// gentler deceleration than full reverse. vehicle_file: absolute, or relative to the guidance
// file's folder or one of its parents (so config/vehicles/x.yaml works).
FollowerParams load_follower_params(const config::Value& v);

// Reverse surge thrust / m11 of a vehicle file (m/s^2): full astern, no drag.
double vehicle_braking_decel(const std::string& vehicle_file);

// The path follower node's own settings (rates and freshness), from the same file.
struct FollowerNodeParams {
  FollowerParams follower;
  double rate_hz = 10;              // setpoint / progress rate
  double odometry_timeout_s = 0.5;  // older odometry counts as absent: setpoint inactive
  // A GNSS outage (odometry_t.DEAD_RECKONING): for this long from its start the setpoint is the
  // one from before it (course and speed held, not steered by a drifting position); then the
  // path is followed on the dead-reckoned estimate again, until tiller-failsafe's GNSS rule
  // (lost_after_s) holds or stops the vehicle (docs/safety.md). 0: follow the estimate at once.
  double outage_hold_course_s = 5.0;
};

FollowerNodeParams load_follower_node_params(const config::Value& root);

}  // namespace tiller::guidance
