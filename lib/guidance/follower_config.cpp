#include "guidance/follower_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "core/config_files.hpp"

namespace tiller::guidance {

double vehicle_braking_decel(const std::string& vehicle_file) {
  const auto root = config::Value::load_file(vehicle_file);
  root.mark_used();    // the mixer and the simulator check this file strictly; we read two parts
  double reverse = 0;  // N astern, summed over the thrusters' surge components
  for (const auto& t : root.at("thrusters").items()) {
    const auto d = t.numbers("direction", 3);
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (norm <= 0) t.at("direction").fail("a non-zero direction");
    reverse += t.number("max_reverse_n", config::Range::at_least(0)) * std::max(0.0, d[0] / norm);
  }
  const config::Value m = root.at("dynamics", "the simulator's dynamics section").at("mass_matrix");
  const double m11 = m[0].as_numbers(0)[0];
  if (!(m11 > 0)) m.fail("a positive surge mass m11 (kg, with added mass)");
  return reverse / m11;
}

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
  if (v.has("braking_decel") && v.at("braking_decel").is_map()) {
    const config::Value b = v.at("braking_decel");
    const double fraction = b.number("fraction", {1e-3, 1});
    const config::Value vf = b.at("vehicle_file", "a vehicle file (config/vehicles/*.yaml)");
    const std::string file = config::resolve_near(vf.as_string(), v.file());
    if (!std::filesystem::exists(file)) {
      vf.fail(
          "a vehicle file (absolute, or relative to this file's folder or one of its "
          "parents); not found: " +
          vf.as_string());
    }
    p.braking_decel = fraction * vehicle_braking_decel(file);
    if (!(p.braking_decel >= 1e-3 && p.braking_decel <= 20)) {
      vf.fail(
          "a vehicle whose reverse thrust gives a braking deceleration in [0.001, 20] m/s^2 "
          "at this fraction; got " +
          std::to_string(p.braking_decel));
    }
  } else {
    p.braking_decel = v.number("braking_decel", {1e-3, 20});
  }
  p.heading_slowdown_angle = v.angle_deg("heading_slowdown_angle_deg", {1, 360});
  p.goal_heading_distance = v.number("goal_heading_distance", nonneg);
  const std::string law =
      v.choice("cross_track_law", {"seed", "world_integral", "los", "integral", "adaptive"});
  p.law = law == "seed"             ? CrossTrackLaw::kSeed
          : law == "world_integral" ? CrossTrackLaw::kWorldIntegral
          : law == "los"            ? CrossTrackLaw::kLos
          : law == "integral"       ? CrossTrackLaw::kIntegral
                                    : CrossTrackLaw::kAdaptive;
  p.integral_gain = v.number("integral_gain", nonneg);
  p.integral_limit = v.number("integral_limit", nonneg);
  p.lookahead = v.number("lookahead_distance", {0.1, 1000});
  p.integral_kappa = v.number("integral_kappa", {1e-6, 100});
  p.adaptive_gamma = v.number("adaptive_gamma", {0, 10});
  p.max_crab = v.angle_deg("max_crab_deg", {0, 80});
  p.integral_zone = v.number("integral_zone", nonneg);
  p.turn_rate = v.number("turn_rate", {0, 10});
  p.turn_drift_rate = v.number("turn_drift_rate", {0, 10});
  // Corners along an arc (issue 35); absent: off, as before.
  p.turn_arc = v.boolean_or("turn_arc", false);
  p.turn_arc_inside_max = v.number_or("turn_arc_inside_max", 0.5, {0.01, 100});
  p.heading_lead_s = v.number_or("heading_lead_s", 0, {0, 10});
  p.turn_arc_water = v.choice_or("turn_arc_frame", "ground", {"ground", "water"}) == "water";
  // The current along a leg from the velocity PID's surge integral (issue 35); absent: off.
  p.surge_integral_drag = v.number_or("surge_integral_drag", 0, {0, 1e5});
  // Corners as a pivot (issue 35, pivot_turn.hpp); absent: off.
  p.turn_pivot = v.boolean_or("turn_pivot", false);
  p.pivot_min_angle = v.angle_deg_or("pivot_min_angle_deg", p.pivot_min_angle, {1, 180});
  p.pivot_turn_rate = v.number_or("pivot_turn_rate", p.pivot_turn_rate, {0.01, 10});
  p.pivot_allowance = v.number_or("pivot_allowance", p.pivot_allowance, {0, 10});
  p.pivot_max_offset = v.number_or("pivot_max_offset", p.pivot_max_offset, {0, 10});
  p.pivot_hold_gain = v.number_or("pivot_hold_gain", p.pivot_hold_gain, {0.01, 10});
  p.pivot_exit_angle = v.angle_deg_or("pivot_exit_angle_deg", p.pivot_exit_angle, {0.1, 90});
  return p;
}

FollowerNodeParams load_follower_node_params(const config::Value& root) {
  FollowerNodeParams n;
  n.follower = load_follower_params(root.at("follower"));
  n.rate_hz = root.number("rate_hz", {0.1, 1000});
  n.odometry_timeout_s = root.number("odometry_timeout_s", {0.001, 60});
  n.outage_hold_course_s = root.number_or("outage_hold_course_s", n.outage_hold_course_s, {0, 600});
  return n;
}

}  // namespace tiller::guidance
