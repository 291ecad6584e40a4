// Loads the path follower's parameters (FollowerParams, see path_follower.hpp) from the
// `follower:` section of a guidance YAML file (config/guidance/*.yaml). Strict: every key is
// required, ranges are checked, angles only under keys ending in _deg.
#pragma once

#include "core/config.hpp"
#include "guidance/path_follower.hpp"

namespace tiller::guidance {

FollowerParams load_follower_params(const config::Value& v);

// The path follower node's own settings (rates and freshness), from the same file.
struct FollowerNodeParams {
  FollowerParams follower;
  double rate_hz = 10;              // setpoint / progress rate
  double odometry_timeout_s = 0.5;  // older odometry counts as absent: setpoint inactive
};

FollowerNodeParams load_follower_node_params(const config::Value& root);

}  // namespace tiller::guidance
