// The command-velocity generator of seed 004 (cmd_vel_generator_node), made explicit.
//
// World frame: local NED, horizontal plane only: positions [north east] m, velocities [north
// east] m/s over ground, headings rad (0 = north, + clockwise), wrapped to (-pi, pi].
//
// Given the vehicle's position and heading, it selects a segment of the path (point 1 = the
// selected point, point 2 = the next one) and commands a velocity that is the sum of
//   * a vector toward the segment's line, speed min(approach_max_speed, e / approach_divisor_s)
//     with e the distance to the line, and
//   * a vector along the segment, max_speed reduced linearly by e (zero at
//     parallel_cutoff_distance), by the coming turn (within turn_slowdown_distance of point 2,
//     a factor 1 - turn_reduction * angle / pi), and by the end of the path (linear as the seed:
//     remaining / end_divisor_s within end_slowdown_distance; or constant deceleration:
//     sqrt(2 * braking_decel * remaining)).
// The whole vector is then scaled by 1 - |heading error| / heading_slowdown_angle (not below
// 0) so the vehicle turns toward the direction of travel first, unless is_translation.
//
// Segment selection is the seed's dot-product test: with s = p2 - p1, a = s.(x - p1) and
// b = s.(x - p2), the vehicle is BEHIND the segment if a < 0, IN FRONT (it passed p2) if b > 0,
// else in the MIDDLE. A segment is done within acceptance_radius of p2, or when the vehicle is
// in front of it (p2 is then skipped if it never came within acceptance_radius); within
// corner_cut_radius of p2 the follower already follows the next segment (the corner cut).
// Passed points are skipped in one update until a segment is found that the vehicle is behind
// or in the middle of. Behind the current segment (other than after a corner cut), farther
// than acceptance_radius from its first point and in the middle of the previous segment, the
// follower steps back to the previous segment, as the seed's notes say it most likely should.
//
// Beyond the seed: an integral cross-track law (integral LOS): a world-frame velocity
// correction integrates the vector from the vehicle to the path, so a steady cross current
// leaves no standing offset (bounded by integral_limit).
//
// Bad paths: consecutive points closer than min_segment_length are merged (repeated points,
// zero-length segments); a one-point path becomes a segment from the vehicle's position to the
// point. update() allocates nothing.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/angles.hpp"

namespace tiller::guidance {

using Vec2 = Eigen::Vector2d;

enum class EndSlowdown { kLinear, kConstantDecel };
enum class CrossTrackLaw { kSeed, kIntegral };
enum class SegmentRelation { kBehind, kMiddle, kInFront };

struct FollowerParams {
  double max_speed = 1.5;                 // m/s along the path
  double acceptance_radius = 1.0;         // m: a point counts as reached within this
  double corner_cut_radius = 1.0;         // m: within this of p2, follow the next segment already
  double min_segment_length = 0.05;       // m: shorter segments are merged away
  double approach_max_speed = 1.0;        // m/s toward the path
  double approach_divisor_s = 2.0;        // s: approach speed = e / this (up to the maximum)
  double parallel_cutoff_distance = 5.0;  // m of cross-track at which the along term is zero
  double turn_slowdown_distance = 5.0;    // m from p2 where the turn slow-down starts
  double turn_reduction = 0.8;            // fraction removed for a 180 deg turn, linear in angle
  double turn_min_fraction = 0.2;         // never below this fraction of max_speed for a turn
  EndSlowdown end_slowdown = EndSlowdown::kConstantDecel;
  double end_slowdown_distance = 6.0;       // m (linear law): slow-down starts here
  double end_divisor_s = 2.0;               // s (linear law): speed = remaining / this
  double braking_decel = 0.25;              // m/s^2 (constant-deceleration law)
  double heading_slowdown_angle = kPi / 2;  // rad: heading error at which speed reaches zero
  double goal_heading_distance = 2.0;       // m: on the last segment, nearer than this (path
                                            // left and straight line), target the goal heading
  CrossTrackLaw law = CrossTrackLaw::kSeed;
  double integral_gain = 0.05;  // 1/s^2: d(correction)/dt = gain * (vector to path)
  double integral_limit = 0.5;  // m/s: bound on the correction's magnitude
  double integral_zone = 3.0;   // m: integrate only when this close to the path
};

struct Waypoint {
  Vec2 position{0, 0};  // [north east] m
  bool has_heading = false;
  double heading = 0;  // rad NED
};

struct FollowerOutput {
  bool active = false;         // false: no path
  Vec2 velocity{0, 0};         // [north east] m/s over ground
  double target_heading = 0;   // rad NED
  bool heading_valid = false;  // false: no heading known yet (hold)
  int segment = -1;            // index of point 1
  SegmentRelation relation = SegmentRelation::kMiddle;
  double cross_track = 0;            // m, signed: + = vehicle right of the path direction
  double along_track_remaining = 0;  // m left along the current segment
  double distance_to_goal = 0;       // m, straight line to the last point
  double remaining_path = 0;         // m, along the path to the last point
  bool complete = false;             // every segment done
  int skipped = 0;                   // points passed without coming within acceptance_radius
  int stepped_back = 0;              // times the follower went back to the previous segment
  // The factors applied (for tuning plots and tests).
  double along_speed = 0, approach_speed = 0, turn_factor = 1, heading_factor = 1;
  Vec2 integral_correction{0, 0};
};

class PathFollower {
 public:
  explicit PathFollower(const FollowerParams& p = {});

  // Starts a new path. `vehicle` and `heading` are the vehicle's pose now (a one-point path
  // starts from there; is_translation without a goal heading holds this heading).
  // Returns false when there is nothing to follow (no points): the follower is then idle.
  bool set_path(const std::vector<Waypoint>& points, const Vec2& vehicle, double heading,
                bool is_translation);
  void clear();
  // Changes is_translation mid-path (TILLER_MODE); `heading` is held if the goal has none.
  void set_translation(bool is_translation, double heading);
  bool has_path() const { return !pts_.empty(); }
  const std::vector<Waypoint>& points() const { return pts_; }
  const FollowerParams& params() const { return p_; }

  // One step: `dt` s since the previous update (for the integral law; 0 is fine).
  FollowerOutput update(const Vec2& pos, double heading, double dt);

  // Speed allowed with `remaining` m of path left (the end slow-down law in force).
  double end_speed(double remaining) const;
  // Factor for a turn of `angle` rad (0..pi).
  double turn_factor(double angle) const;

  bool goal_heading_valid() const { return goal_heading_valid_; }
  double goal_heading() const { return goal_heading_; }

 private:
  FollowerParams p_;
  std::vector<Waypoint> pts_;
  std::vector<double> tail_length_;  // path length from point k to the end
  std::vector<double> min_dist_;     // closest approach to each point so far
  int seg_ = 0;
  bool complete_ = false;
  int skipped_ = 0;
  int stepped_back_ = 0;
  bool entered_by_cut_ = false;   // the current segment was taken early, by the corner cut
  bool entered_by_skip_ = false;  // ... by passing its first point outside acceptance_radius
  bool is_translation_ = false;
  bool goal_heading_valid_ = false;
  double goal_heading_ = 0;
  double last_heading_ = 0;
  bool last_heading_valid_ = false;
  Vec2 integral_{0, 0};
};

}  // namespace tiller::guidance
