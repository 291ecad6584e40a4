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
// world_integral: the seed's law plus a world-frame velocity correction integrating the vector
// to the path (bounded by integral_limit). At a segment switch only its component along the new
// segment's normal is kept (issue 13 finding 2: kept whole, after a 90 deg turn it pointed along
// the new leg), and the commanded velocity is scaled down to max_speed when above it.
//
// Beyond the seed, three line-of-sight (LOS) cross-track laws (docs/algorithms.md has the
// sources). With pi_p the segment's direction, e the cross-track error (+ right of the path)
// and Delta the lookahead distance, the commanded heading is
//   los:       pi_p - atan(e / Delta)
//   integral:  pi_p - atan((e + kappa * y_int) / Delta),                    (ILOS, Borhaug 2008)
//              d(y_int)/dt = Delta * e / ((e + kappa * y_int)^2 + Delta^2)
//   adaptive:  pi_p - beta_hat - atan(e / Delta),                          (ALOS, Fossen 2023)
//              d(beta_hat)/dt = gamma * Delta * e / sqrt(Delta^2 + e^2)
// and the velocity is that heading times the along-path speed (max_speed with the turn, end and
// heading slow-downs; never above max_speed). The state (y_int, beta_hat) lives in the PATH
// frame: it integrates only within integral_zone of the path and not within
// turn_slowdown_distance after a corner (the turn's error is not the current's). It stands for the
// crab angle that cancels the current's component along the path's normal. At a segment switch the
// normal turns by the turn angle d; the known component is projected onto the new normal (sin beta'
// = sin beta * cos d: 90 deg resets it, a hairpin flips it) and the unknown along-path component
// taken as zero. The crab angle is bounded by max_crab.
//
// Turn anticipation (turn_rate > 0, any law): a segment is left at the wheel-over point, at
// R * tan(d / 2) before its end point (R = U / turn_rate, U = max_speed * the turn factor: the
// turn's speed), so the turn ends on the next leg instead of outside it; the turn's slow-down
// then also holds within turn_slowdown_distance after the corner (the turn is flown there).
//
// In a current (turn_drift_rate > 0), the wheel-over point moves by the drift the law's current
// estimate (current_estimate()) predicts during the turn: outward part c_out (across the new leg,
// toward the old leg's direction) times angle / turn_drift_rate, over sin(angle) (a point moved
// back along the old leg by x moves the turn's end across the new leg by x sin(angle)); bounded
// to [-R tan(d/2), 3 max(R tan(d/2), 1 m)]. An underactuated boat cannot push sideways while it
// turns: the turn itself carries it c_out * T outward (issue 13: 1.5 m outside in 0.3 m/s).
//
// Corners along an arc (turn_arc): a corner of up to 120 deg is flown along the fillet of radius
// R = U / turn_rate tangent to both legs (turn_arc.hpp), U the turn's speed (max_speed * the turn
// factor), R at most what passes turn_arc_inside_max inside the corner (U then R * turn_rate);
// the segment is left at the arc's start, R tan(d / 2) before the corner (the wheel-over point),
// and the speed is U from turn_slowdown_distance before it. On the arc the velocity is U along
// it plus, along the radius, the approach toward the arc (as on a leg, e / approach_divisor_s)
// and the law's current correction's radial part (current_estimate(): what the legs so far
// learnt of the current, the whole current from the second corner on): the current is
// countered through the turn instead of carrying the boat outward at c for the turn's duration.
// The course turns at U / R; the heading setpoint leads the velocity's direction by that rate
// times heading_lead_s (the heading loop's lag, 1 / heading_kp for a proportional loop): the
// course-rate feed-forward a heading-only setpoint can carry. Off the arc by more than
// parallel_cutoff_distance, or past its end, the follower follows the outgoing leg.
//
// Bad paths: consecutive points closer than min_segment_length are merged (repeated points,
// zero-length segments); a one-point path becomes a segment from the vehicle's position to the
// point. update() allocates nothing.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/angles.hpp"
#include "guidance/turn_arc.hpp"

namespace tiller::guidance {

using Vec2 = Eigen::Vector2d;

enum class EndSlowdown { kLinear, kConstantDecel };
enum class CrossTrackLaw { kSeed, kWorldIntegral, kLos, kIntegral, kAdaptive };
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
  double integral_gain = 0.05;    // 1/s^2 (world_integral): d(correction)/dt = gain * to path
  double integral_limit = 0.5;    // m/s (world_integral): bound on the correction
  double lookahead = 5.0;         // m: Delta (los, integral, adaptive)
  double integral_kappa = 1.0;    // m/s: kappa (integral)
  double adaptive_gamma = 0.005;  // rad/(m s): gamma (adaptive)
  double max_crab = 0.5;          // rad: bound on the crab angle of the integral / adaptive state
  double integral_zone = 3.0;     // m: integrate only when this close to the path
  double turn_rate = 0;           // rad/s: wheel-over from R = U / turn_rate; 0: none (the seed)
  double turn_drift_rate = 0;     // rad/s: with turn_rate, the wheel-over moves by the current's
                                  // drift over angle / this (the estimate's outward part); 0: off
  // Corners along an arc (turn_arc, with turn_rate > 0; turns up to 120 deg): see below.
  bool turn_arc = false;
  double turn_arc_inside_max = 0.5;  // m: the arc passes at most this far inside the corner
  double heading_lead_s = 0;         // s: the heading setpoint leads the course by rate * this
  // turn_arc through the water (turn_arc_frame: water): the corner is a WaterTurn (turn_arc.hpp)
  // at the arc's speed and turn_rate, planned from current_full() when the leg is left.
  bool turn_arc_water = false;
  // N per (m/s): the velocity PID's surge drag feed-forward (its k_drag). > 0: the node takes the
  // current along the heading from that PID's surge integral (TILLER_PID_VELOCITY: at a steady
  // speed I = -k_drag * current along the heading) and hands it to observe_current_along(); 0: off.
  double surge_integral_drag = 0;
  // Corners flown as a pivot (turn_pivot, pivot_turn.hpp): a corner of at least pivot_min_angle
  // is flown by stopping at the pivot point S (set back from the corner by pivot_setback), turning
  // in place while S is held (velocity pivot_hold_gain * (S - position), at most
  // approach_max_speed) to the outgoing leg's heading, and leaving S when the heading is within
  // pivot_exit_angle of it (or after pivot_timeout_s). The approach brakes at braking_decel to S.
  bool turn_pivot = false;
  double pivot_min_angle = kPi / 4;    // rad: smaller corners keep the wheel-over
  double pivot_turn_rate = 0.3;        // rad/s: the hull's turn rate in place (the drift's time)
  double pivot_allowance = 0.1;        // m: accepted past the next leg's line
  double pivot_max_offset = 0.8;       // m: S at most this far before the corner
  double pivot_hold_gain = 0.5;        // 1/s: velocity toward S per metre
  double pivot_exit_angle = kPi / 12;  // rad: heading error at which the pivot ends
  double pivot_trigger = 0.1;          // m: the pivot starts this far (along the leg) before S
  double pivot_timeout_s = 30;         // s: the pivot ends after this whatever the heading
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
  double crab = 0;        // rad: the integral / adaptive state as a crab angle (+ = to the left)
  double wheel_over = 0;  // m before the end point where the segment is left (turn anticipation)
  bool on_arc = false;    // a corner is flown along its arc (turn_arc)
  bool pivot = false;     // turning in place at a pivot point (turn_pivot)
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
  // The along-path speed from now on (a mission's speed change, TILLER_PATH_SPEED), m/s > 0.
  void set_max_speed(double v) { p_.max_speed = v; }

  // One step: `dt` s since the previous update (for the integral law; 0 is fine).
  FollowerOutput update(const Vec2& pos, double heading, double dt);

  // Speed allowed with `remaining` m of path left (the end slow-down law in force).
  double end_speed(double remaining) const;
  // Heading the LOS laws command for cross-track error `e` on a segment of direction `path`.
  double los_heading(double path, double e) const;
  // Wheel-over distance for a turn of `angle` rad (0..pi) at speed `speed`: R * tan(angle / 2)
  // with R = speed / turn_rate, a turn above 120 deg taken as 120 (tan 60 deg: hairpins); 0 without
  // turn_rate.
  double wheel_over(double angle, double speed) const;
  // The law's state: y_int (integral, s) or beta_hat (adaptive, rad).
  double state() const { return state_; }
  void set_state(double s) { state_ = s; }
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
  Vec2 world_integral_{0, 0};  // world_integral's correction, m/s NED
  double state_ = 0;           // y_int (integral) or beta_hat (adaptive), path frame
  Vec2 crab_world_{0, 0};      // integral / adaptive: sin(crab) along the left normal, world frame,
                               // each leg's normal component kept (carry_state)
  TurnArc arc_;                // the corner being flown (turn_arc)
  WaterTurn wturn_;            // ... through the water (turn_arc_water)
  Vec2 wturn_origin_{0, 0};    // m NED: where it started
  double wturn_tau_ = 0;       // s into it
  bool on_arc_ = false;
  double arc_speed_ = 0;  // m/s along it
  Vec2 last_pos_{0, 0};   // at the last update() (observe_current_along's gate)
  bool last_pos_valid_ = false;
  // The pivot (turn_pivot): at the end of segment pivot_seg_, S = pivot_point_.
  int pivot_seg_ = -1;
  bool pivot_active_ = false, pivot_done_ = false;
  Vec2 pivot_point_{0, 0};
  double pivot_heading_ = 0;         // rad NED: the outgoing leg's heading, its crab included
  double pivot_time_ = 0;            // s since the pivot started
  bool pivot_corner(int seg) const;  // the corner at the end of `seg` is flown as a pivot
  void reset_pivot();
  int along_seg_ = -1;        // the leg the along-leg current was measured on (-1: none)
  double along_current_ = 0;  // m/s along that leg
  double crab() const;
  // The arc's radius and speed for a turn of `angle` rad (turn_arc); radius 0: no arc.
  void arc_for(double angle, double& radius, double& speed) const;
  double drift_lead(const Vec2& t1, const Vec2& t2, double angle) const;

 public:
  // The world-frame current estimate the law holds (m/s NED; what it has learnt on each leg of
  // the current across it): world_integral -correction, integral / adaptive -sin(crab) * speed.
  Vec2 current_estimate() const;
  // A measurement of the current along `heading` (rad NED): `current` m/s (+ toward the heading),
  // e.g. from the velocity PID's surge integral at a steady speed. Taken only on a leg (not after
  // completion), at least kAlongSettleDistance past its first point and before its turn slow-down
  // (by kAlongSettleDistance again), with the heading within 30 deg of the leg (at the position of
  // the last update()). On that leg it replaces the law's estimate's part along the leg, which the
  // law cannot observe (on the first leg it is zero): current_full(). Allocates nothing.
  void observe_current_along(double heading, double current);
  // current_estimate() with its part along the present leg measured (observe_current_along() on
  // this leg), else current_estimate(). What the turn anticipation predicts the drift from.
  Vec2 current_full() const;
  static constexpr double kAlongSettleDistance = 15.0;  // m past a leg's first point

 private:
  void carry_state(int from_seg, int to_seg);
};

}  // namespace tiller::guidance
