#include "guidance/follower_config.hpp"

namespace tiller::guidance {

FollowerParams load_follower_params(const config::Value& v) {
  using config::Range;
  FollowerParams p;
  const Range pos = Range::positive();
  const Range nonneg = Range::at_least(0);
  p.max_speed = v.number("max_speed", {0.01, 10});
  p.acceptance_radius = v.number("acceptance_radius", pos);
  p.corner_cut_radius = v.number("corner_cut_radius", nonneg);
  p.min_segment_length = v.number("min_segment_length", {1e-6, 10});
  p.approach_max_speed = v.number("approach_max_speed", {0, 10});
  p.approach_divisor_s = v.number("approach_divisor_s", pos);
  p.parallel_cutoff_distance = v.number("parallel_cutoff_distance", pos);
  p.turn_slowdown_distance = v.number("turn_slowdown_distance", nonneg);
  p.turn_reduction = v.number("turn_reduction", {0, 1});
  p.turn_min_fraction = v.number("turn_min_fraction", {0, 1});
  p.end_slowdown = v.choice("end_slowdown", {"linear", "constant_decel"}) == "linear"
                       ? EndSlowdown::kLinear
                       : EndSlowdown::kConstantDecel;
  p.end_slowdown_distance = v.number("end_slowdown_distance", nonneg);
  p.end_divisor_s = v.number("end_divisor_s", pos);
  p.braking_decel = v.number("braking_decel", {1e-3, 20});
  p.heading_slowdown_angle = v.angle_deg("heading_slowdown_angle_deg", {1, 360});
  p.goal_heading_distance = v.number("goal_heading_distance", nonneg);
  p.law = v.choice("cross_track_law", {"seed", "integral"}) == "seed" ? CrossTrackLaw::kSeed
                                                                      : CrossTrackLaw::kIntegral;
  p.integral_gain = v.number("integral_gain", nonneg);
  p.integral_limit = v.number("integral_limit", nonneg);
  p.integral_zone = v.number("integral_zone", nonneg);
  return p;
}

FollowerNodeParams load_follower_node_params(const config::Value& root) {
  FollowerNodeParams n;
  n.follower = load_follower_params(root.at("follower"));
  n.rate_hz = root.number("rate_hz", {0.1, 1000});
  n.odometry_timeout_s = root.number("odometry_timeout_s", {0.001, 60});
  return n;
}

}  // namespace tiller::guidance
