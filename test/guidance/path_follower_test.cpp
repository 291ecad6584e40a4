// The seed-004 command-velocity generator: every behaviour against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/config.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower.hpp"

namespace tiller::guidance {
namespace {

// Seed-like parameters with round numbers (the hand computations below use them).
FollowerParams seed_params() {
  FollowerParams p;
  p.max_speed = 1.5;
  p.acceptance_radius = 1.0;
  p.corner_cut_radius = 1.0;
  p.min_segment_length = 0.05;
  p.approach_max_speed = 1.0;
  p.approach_divisor_s = 2.0;
  p.parallel_cutoff_distance = 5.0;
  p.turn_slowdown_distance = 5.0;
  p.turn_reduction = 0.8;
  p.turn_min_fraction = 0.2;
  p.end_slowdown = EndSlowdown::kLinear;
  p.end_slowdown_distance = 6.0;
  p.end_divisor_s = 2.0;
  p.braking_decel = 0.25;
  p.heading_slowdown_angle = kPi / 2;
  p.goal_heading_distance = 2.0;
  p.law = CrossTrackLaw::kSeed;
  return p;
}

std::vector<Waypoint> pts(std::initializer_list<std::pair<double, double>> l) {
  std::vector<Waypoint> v;
  for (auto [n, e] : l) {
    Waypoint w;
    w.position = Vec2(n, e);
    v.push_back(w);
  }
  return v;
}

TEST(PathFollower, VectorSumTowardAndAlongThePath) {
  PathFollower f(seed_params());
  ASSERT_TRUE(f.set_path(pts({{0, 0}, {20, 0}}), Vec2(2, 1), 0.0, false));
  // 1 m east (right) of a path going north, 18 m from the end.
  const auto o = f.update(Vec2(2, 1), 0.0, 0.1);
  EXPECT_EQ(o.segment, 0);
  EXPECT_EQ(o.relation, SegmentRelation::kMiddle);
  EXPECT_DOUBLE_EQ(o.cross_track, 1.0);
  EXPECT_DOUBLE_EQ(o.along_track_remaining, 18.0);
  EXPECT_DOUBLE_EQ(o.approach_speed, 0.5);     // 1 m / 2 s
  EXPECT_DOUBLE_EQ(o.along_speed, 1.5 * 0.8);  // 1 - 1/5 of max speed
  // Target heading along (1.2, -0.5); heading error reduces the speed linearly to 0 at 90 deg.
  const double psi = std::atan2(-0.5, 1.2);
  EXPECT_NEAR(o.target_heading, psi, 1e-12);
  const double k = 1.0 - std::abs(psi) / (kPi / 2);
  EXPECT_NEAR(o.heading_factor, k, 1e-12);
  EXPECT_NEAR(o.velocity.x(), 1.2 * k, 1e-12);
  EXPECT_NEAR(o.velocity.y(), -0.5 * k, 1e-12);
}

TEST(PathFollower, FarFromThePathOnlyTheApproachTermRemains) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {50, 0}}), Vec2(10, -7), kPi / 2, false);
  const auto o = f.update(Vec2(10, -7), kPi / 2, 0.1);  // 7 m left, facing east (toward the path)
  EXPECT_DOUBLE_EQ(o.cross_track, -7.0);
  EXPECT_DOUBLE_EQ(o.along_speed, 0.0);
  EXPECT_DOUBLE_EQ(o.approach_speed, 1.0);  // capped
  EXPECT_NEAR(o.velocity.x(), 0.0, 1e-12);
  EXPECT_NEAR(o.velocity.y(), 1.0, 1e-12);
}

TEST(PathFollower, BehindMiddleInFrontByDotProducts) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  EXPECT_EQ(f.update(Vec2(-2, 0.5), 0, 0).relation, SegmentRelation::kBehind);
  EXPECT_EQ(f.update(Vec2(-2, 0.5), 0, 0).segment, 0);  // behind the first: nothing before it
  EXPECT_EQ(f.update(Vec2(5, 3), 0, 0).relation, SegmentRelation::kMiddle);
  // In front of segment 0 (passed (10,0) 3 m away): moves on; middle of segment 1.
  const auto o = f.update(Vec2(12, 3), 0, 0);
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.relation, SegmentRelation::kMiddle);
  EXPECT_EQ(o.skipped, 1);
}

// The seed's notes: behind the segment, "most likely the vehicle should decrement the selected
// point, as it is likely on the previous line segment", except after a corner cut.
TEST(PathFollower, BehindStepsBackToThePreviousSegmentExceptAfterACornerCut) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  // Passes (10, 0) 3 m to its west, in front of segment 0: moves on, (10, 0) skipped.
  auto o = f.update(Vec2(10.5, -3), 0, 0);
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.skipped, 1);
  EXPECT_EQ(o.relation, SegmentRelation::kBehind);  // of segment 1, and in front of segment 0
  // Set back (a current): behind segment 1 and in the middle of segment 0, 3.6 m from (10, 0):
  // back to segment 0, and (10, 0) is no longer counted as skipped.
  o = f.update(Vec2(8, -3), 0, 0);
  EXPECT_EQ(o.segment, 0);
  EXPECT_EQ(o.relation, SegmentRelation::kMiddle);
  EXPECT_EQ(o.skipped, 0);
  EXPECT_EQ(o.stepped_back, 1);
  EXPECT_GT(o.velocity.y(), 0.0);  // toward segment 0's line
  // Reaches (10, 0) this time: segment 1, nothing skipped.
  o = f.update(Vec2(9.5, -0.2), 0, 0);
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.skipped, 0);

  // After a corner cut (within corner_cut_radius of (10, 0)), behind the next segment: keeps it.
  PathFollower g(seed_params());
  g.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  EXPECT_EQ(g.update(Vec2(9.3, -0.5), 0, 0).segment, 1);  // the cut
  o = g.update(Vec2(8.5, -1.5), 0, 0);                    // drifted back, 2.1 m from the corner
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.relation, SegmentRelation::kBehind);
  EXPECT_EQ(o.stepped_back, 0);
  // Behind but within acceptance_radius of the corner: no back-and-forth.
  PathFollower h(seed_params());
  h.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  h.update(Vec2(10.5, -3), 0, 0);  // skipped, as above
  o = h.update(Vec2(9.6, -0.5), 0, 0);
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.stepped_back, 0);
}

TEST(PathFollower, SkipsEveryPassedPointInOneUpdate) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {5, 0}, {10, 0}, {15, 0}, {20, 0}}), Vec2(0, 0), 0, false);
  const auto o = f.update(Vec2(16, 2), 0, 0);
  EXPECT_EQ(o.segment, 3);
  EXPECT_EQ(o.skipped, 3);  // (5,0), (10,0), (15,0): never within 1 m
  EXPECT_FALSE(o.complete);
}

TEST(PathFollower, WithinAcceptanceRadiusThePointIsReachedNotSkipped) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  const auto o = f.update(Vec2(9.5, 0.2), 0, 0);
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.skipped, 0);
  const auto o2 = f.update(Vec2(9.0, 0.2), 0, 0);  // does not go back
  EXPECT_EQ(o2.segment, 1);
}

TEST(PathFollower, LooksAheadToCutTheCorner) {
  auto p = seed_params();
  p.acceptance_radius = 0.5;
  p.corner_cut_radius = 1.0;
  PathFollower f(p);
  f.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  EXPECT_EQ(f.update(Vec2(8.9, 0), 0, 0).segment, 0);  // 1.1 m: not yet
  const auto o = f.update(Vec2(9.3, -0.3), 0, 0);      // 0.76 m: follow the next segment
  EXPECT_EQ(o.segment, 1);
  EXPECT_EQ(o.skipped, 0);
  EXPECT_EQ(o.relation, SegmentRelation::kBehind);  // behind the next segment, as the seed says
}

TEST(PathFollower, SlowsDownForTurns) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}, {10, 10}}), Vec2(0, 0), 0, false);
  const auto far = f.update(Vec2(4, 0), 0, 0);  // 6 m from the turn: no slow-down
  EXPECT_DOUBLE_EQ(far.turn_factor, 1.0);
  EXPECT_DOUBLE_EQ(far.along_speed, 1.5);
  const auto o = f.update(Vec2(7, 0), 0, 0);  // 3 m from a 90 deg turn
  EXPECT_DOUBLE_EQ(o.turn_factor, 1.0 - 0.8 * 0.5);
  EXPECT_DOUBLE_EQ(o.along_speed, 1.5 * 0.6);
  EXPECT_NEAR(o.velocity.x(), 0.9, 1e-12);
  EXPECT_DOUBLE_EQ(f.turn_factor(kPi), 0.2);  // hairpin: floor
}

TEST(PathFollower, EndSlowDownLinearAsTheSeedAndConstantDeceleration) {
  auto p = seed_params();
  PathFollower lin(p);
  EXPECT_DOUBLE_EQ(lin.end_speed(7.0), 1.5);  // before the slow-down distance
  EXPECT_DOUBLE_EQ(lin.end_speed(2.0), 1.0);  // 2 m / 2 s
  EXPECT_DOUBLE_EQ(lin.end_speed(0.5), 0.25);
  p.end_slowdown = EndSlowdown::kConstantDecel;
  PathFollower cd(p);
  EXPECT_DOUBLE_EQ(cd.end_speed(10.0), 1.5);         // sqrt(5) capped
  EXPECT_DOUBLE_EQ(cd.end_speed(2.0), 1.0);          // sqrt(2 * 0.25 * 2)
  EXPECT_DOUBLE_EQ(cd.end_speed(0.5), 0.5);          // sqrt(2 * 0.25 * 0.5)
  EXPECT_GT(cd.end_speed(1.0), lin.end_speed(1.0));  // holds speed longer
  // Through update(): 3 m left of a 10 m path, linear: 1.5 m/s; 2 m left: 1.0 m/s.
  lin.set_path(pts({{0, 0}, {10, 0}}), Vec2(0, 0), 0, false);
  EXPECT_DOUBLE_EQ(lin.update(Vec2(8, 0), 0, 0).velocity.x(), 1.0);
}

TEST(PathFollower, HeadingErrorReducesSpeedUnlessTranslating) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {20, 0}}), Vec2(2, 0), kPi / 2, false);
  const auto o = f.update(Vec2(2, 0), kPi / 2, 0);  // facing east, path goes north
  EXPECT_DOUBLE_EQ(o.heading_factor, 0.0);
  EXPECT_DOUBLE_EQ(o.velocity.norm(), 0.0);
  EXPECT_DOUBLE_EQ(o.target_heading, 0.0);  // turn toward the path direction first
  const auto o45 = f.update(Vec2(2, 0), kPi / 4, 0);
  EXPECT_NEAR(o45.velocity.x(), 0.75, 1e-12);

  PathFollower t(seed_params());
  t.set_path(pts({{0, 0}, {20, 0}}), Vec2(2, 0), kPi / 2, true);  // is_translation
  const auto ot = t.update(Vec2(2, 0), kPi / 2, 0);
  EXPECT_DOUBLE_EQ(ot.velocity.x(), 1.5);
  EXPECT_DOUBLE_EQ(ot.target_heading, kPi / 2);  // holds its heading (no goal heading)
}

TEST(PathFollower, GoalHeadingNearTheGoal) {
  PathFollower f(seed_params());
  auto p = pts({{0, 0}, {10, 0}, {10, 10}});
  p.back().has_heading = true;
  p.back().heading = -kPi / 2;
  f.set_path(p, Vec2(0, 0), 0, false);
  f.update(Vec2(9.5, 0), 0, 0);
  EXPECT_NEAR(f.update(Vec2(10, 5), kPi / 2, 0).target_heading, kPi / 2, 1e-12);
  const auto o = f.update(Vec2(10, 8.5), kPi / 2, 0);  // 1.5 m from the goal
  EXPECT_DOUBLE_EQ(o.target_heading, -kPi / 2);
  EXPECT_DOUBLE_EQ(o.heading_factor, 1.0);  // no slow-down for the goal heading
}

// A closed course starts where it ends: the goal heading (here 180 deg) applies only on the
// last segment near the goal, never at the start of the first leg (the old rule, "within
// goal_heading_distance of the goal on any segment", told the boat to face south at the start).
TEST(PathFollower, ClosedCourseStartsAlongTheFirstLegNotAtTheGoalHeading) {
  PathFollower f(seed_params());
  auto p = pts({{0, 0}, {20, 0}, {20, 12}, {0, 12}, {0, 0}});
  p.back().has_heading = true;
  p.back().heading = kPi;
  f.set_path(p, Vec2(0, 0), 0, false);
  for (double n = 0; n <= 2.0; n += 0.25) {
    const auto o = f.update(Vec2(n, 0.1), 0, 0);
    SCOPED_TRACE(n);
    EXPECT_EQ(o.segment, 0);
    EXPECT_LT(o.distance_to_goal, 2.1);
    EXPECT_NEAR(o.target_heading, 0.0, 0.06);  // along the first leg (plus the approach term)
    EXPECT_GT(o.heading_factor, 0.9);
  }
  // On the last leg, 1.5 m (path and straight line) from the goal: the goal heading.
  f.update(Vec2(20, 0), 0, 0);
  f.update(Vec2(20, 12), kPi / 2, 0);
  f.update(Vec2(0, 12), kPi, 0);
  EXPECT_NEAR(f.update(Vec2(0, 5), -kPi / 2, 0).target_heading, -kPi / 2, 0.05);  // 5 m: along
  const auto o = f.update(Vec2(0, 1.5), -kPi / 2, 0);
  EXPECT_EQ(o.segment, 3);
  EXPECT_DOUBLE_EQ(o.target_heading, kPi);
}

TEST(PathFollower, CompletesAtTheLastPointAndThenHeadsForTheGoal) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}}), Vec2(0, 0), 0, false);
  EXPECT_FALSE(f.update(Vec2(8.5, 0), 0, 0).complete);
  const auto o = f.update(Vec2(9.5, 0), 0, 0);
  EXPECT_TRUE(o.complete);
  EXPECT_EQ(o.segment, 1);
  EXPECT_DOUBLE_EQ(o.distance_to_goal, 0.5);
  EXPECT_NEAR(o.velocity.x(), 0.25, 1e-12);  // linear end law: 0.5 m / 2 s, toward the goal
  // Overshoots: still complete, turns around (heading factor 0 while facing away), comes back.
  EXPECT_DOUBLE_EQ(f.update(Vec2(11, 0), 0, 0).velocity.norm(), 0.0);
  const auto o2 = f.update(Vec2(11, 0), kPi, 0);
  EXPECT_TRUE(o2.complete);
  EXPECT_LT(o2.velocity.x(), 0.0);
}

TEST(PathFollower, PassingTheLastPointCompletesTheCourse) {
  PathFollower f(seed_params());
  f.set_path(pts({{0, 0}, {10, 0}}), Vec2(0, 0), 0, false);
  const auto o = f.update(Vec2(11, 3), 0, 0);
  EXPECT_TRUE(o.complete);
  EXPECT_EQ(o.skipped, 1);
}

TEST(PathFollower, BadPaths) {
  PathFollower f(seed_params());
  // Repeated points and zero-length segments are merged.
  ASSERT_TRUE(
      f.set_path(pts({{0, 0}, {0, 0}, {10, 0}, {10, 0}, {10, 0.01}}), Vec2(0, 0), 0, false));
  EXPECT_EQ(f.points().size(), 2u);
  const auto o = f.update(Vec2(5, 0), 0, 0.1);
  EXPECT_TRUE(o.velocity.allFinite());
  EXPECT_DOUBLE_EQ(o.velocity.x(), 1.5);
  // One point: a segment from where the vehicle is.
  ASSERT_TRUE(f.set_path(pts({{10, 0}}), Vec2(0, 0), 0, false));
  ASSERT_EQ(f.points().size(), 2u);
  EXPECT_EQ(f.points()[0].position, Vec2(0, 0));
  EXPECT_DOUBLE_EQ(f.update(Vec2(3, 0), 0, 0).velocity.x(), 1.5);
  // One point where the vehicle already is: complete at once, finite output.
  ASSERT_TRUE(f.set_path(pts({{1, 1}}), Vec2(1, 1), 0, false));
  const auto c = f.update(Vec2(1, 1), 0, 0);
  EXPECT_TRUE(c.complete);
  EXPECT_TRUE(c.velocity.allFinite());
  EXPECT_DOUBLE_EQ(c.velocity.norm(), 0.0);
  // All points the same: one point.
  ASSERT_TRUE(f.set_path(pts({{3, 3}, {3, 3}, {3, 3}}), Vec2(0, 0), 0, false));
  EXPECT_EQ(f.points().size(), 2u);
  // Nothing: idle. NaN points are ignored.
  EXPECT_FALSE(f.set_path({}, Vec2(0, 0), 0, false));
  EXPECT_FALSE(f.update(Vec2(0, 0), 0, 0).active);
  EXPECT_FALSE(f.set_path(pts({{NAN, 0}}), Vec2(0, 0), 0, false));
  // NaN vehicle state: inactive output, no NaN out.
  f.set_path(pts({{0, 0}, {10, 0}}), Vec2(0, 0), 0, false);
  const auto n = f.update(Vec2(NAN, 0), 0, 0);
  EXPECT_FALSE(n.active);
  EXPECT_TRUE(n.velocity.allFinite());
}

// A vehicle that does exactly what it is told, plus a current across the path: the seed's law
// settles where the approach speed cancels the current (e/2 = 0.26 m/s -> 0.52 m off the path);
// the integral law removes the offset.
double standing_offset(CrossTrackLaw law) {
  auto p = seed_params();
  p.law = law;
  p.integral_gain = 0.05;
  p.integral_limit = 0.5;
  p.integral_zone = 3.0;
  PathFollower f(p);
  f.set_path(pts({{0, 0}, {1000, 0}}), Vec2(0, 0), 0, false);
  Vec2 x(0, 0);
  const Vec2 current(0, 0.26);
  double heading = 0;
  FollowerOutput o;
  for (int k = 0; k < 3000; ++k) {  // 300 s at 10 Hz
    o = f.update(x, heading, 0.1);
    heading = o.target_heading;
    x += (o.velocity + current) * 0.1;
  }
  return o.cross_track;
}

TEST(PathFollower, IntegralLawRemovesTheStandingOffsetOfACrossCurrent) {
  EXPECT_NEAR(standing_offset(CrossTrackLaw::kSeed), 0.52, 0.01);
  EXPECT_LT(std::abs(standing_offset(CrossTrackLaw::kWorldIntegral)), 0.02);
  EXPECT_LT(std::abs(standing_offset(CrossTrackLaw::kIntegral)), 0.02);
}

TEST(FollowerConfig, LoadsTheShippedFilesStrictly) {
  for (const char* f : {"config/guidance/default.yaml", "config/guidance/seed.yaml"}) {
    const auto root = config::Value::load_file(std::string(TILLER_SOURCE_DIR) + "/" + f);
    const auto p = load_follower_node_params(root);
    EXPECT_NO_THROW(root.check_all_used()) << f;
    EXPECT_DOUBLE_EQ(p.follower.acceptance_radius, 1.0);
    EXPECT_NEAR(p.follower.heading_slowdown_angle, kPi / 2, 1e-12);
  }
  const auto bad = config::Value::parse(
      "rate_hz: 10\nodometry_timeout_s: 0.5\nfollower: {max_speed: 1}\n", "bad.yaml");
  try {
    load_follower_node_params(bad);
    FAIL() << "expected a config error";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("acceptance_radius"), std::string::npos);
  }
}

// The per-vehicle guidance files are default.yaml with the braking deceleration derived from
// the vehicle's braking ability: 16 % of (reverse surge thrust / surge mass with added mass).
TEST(FollowerConfig, PerVehicleFilesDeriveTheBrakingFromTheVehicle) {
  const std::string src = TILLER_SOURCE_DIR;
  const auto def =
      load_follower_node_params(config::Value::load_file(src + "/config/guidance/default.yaml"));
  struct V {
    const char* name;
    double reverse_n, m11;
    double turn_rate;        // rad/s: the vehicle's own (turn anticipation); default.yaml's is 0
    double turn_drift_rate;  // rad/s: the current's drift in a turn; default.yaml's is 0
  };
  const V vehicles[] = {{"otter", 2 * 66.7, 85.5, 0.7, 0.45},                      // two propellers
                        {"seed004_usv_x", 4 * 100.0 * std::sqrt(0.5), 180, 0, 0},  // 4 at 45 deg
                        {"seed004_usv_h", 4 * 100.0, 180, 0, 0}};  // side pair: no surge
  for (const auto& v : vehicles) {
    SCOPED_TRACE(v.name);
    const auto root =
        config::Value::load_file(src + "/config/guidance/" + std::string(v.name) + ".yaml");
    const auto p = load_follower_node_params(root);
    EXPECT_NO_THROW(root.check_all_used());
    EXPECT_NEAR(vehicle_braking_decel(src + "/config/vehicles/" + v.name + ".yaml"),
                v.reverse_n / v.m11, 1e-9);
    EXPECT_NEAR(p.follower.braking_decel, 0.16 * v.reverse_n / v.m11, 1e-9);
    // Everything else as default.yaml.
    EXPECT_EQ(p.follower.turn_rate, v.turn_rate);
    EXPECT_EQ(p.follower.turn_drift_rate, v.turn_drift_rate);
    auto q = p;
    q.follower.braking_decel = def.follower.braking_decel;
    q.follower.turn_rate = def.follower.turn_rate;
    q.follower.turn_drift_rate = def.follower.turn_drift_rate;
    const auto& a = q.follower;
    const auto& b = def.follower;
    const double av[] = {a.max_speed,
                         a.acceptance_radius,
                         a.corner_cut_radius,
                         a.min_segment_length,
                         a.approach_max_speed,
                         a.approach_divisor_s,
                         a.parallel_cutoff_distance,
                         a.turn_slowdown_distance,
                         a.turn_reduction,
                         a.turn_min_fraction,
                         a.end_slowdown_distance,
                         a.end_divisor_s,
                         a.braking_decel,
                         a.heading_slowdown_angle,
                         a.goal_heading_distance,
                         a.integral_gain,
                         a.integral_limit,
                         a.lookahead,
                         a.integral_kappa,
                         a.adaptive_gamma,
                         a.max_crab,
                         a.integral_zone};
    const double bv[] = {b.max_speed,
                         b.acceptance_radius,
                         b.corner_cut_radius,
                         b.min_segment_length,
                         b.approach_max_speed,
                         b.approach_divisor_s,
                         b.parallel_cutoff_distance,
                         b.turn_slowdown_distance,
                         b.turn_reduction,
                         b.turn_min_fraction,
                         b.end_slowdown_distance,
                         b.end_divisor_s,
                         b.braking_decel,
                         b.heading_slowdown_angle,
                         b.goal_heading_distance,
                         b.integral_gain,
                         b.integral_limit,
                         b.lookahead,
                         b.integral_kappa,
                         b.adaptive_gamma,
                         b.max_crab,
                         b.integral_zone};
    for (std::size_t k = 0; k < std::size(av); ++k) EXPECT_EQ(av[k], bv[k]) << "field " << k;
    EXPECT_EQ(a.end_slowdown, b.end_slowdown);
    EXPECT_EQ(a.law, b.law);
    EXPECT_EQ(a.turn_rate, b.turn_rate);
    EXPECT_EQ(a.turn_drift_rate, b.turn_drift_rate);
    EXPECT_EQ(q.rate_hz, def.rate_hz);
    EXPECT_EQ(q.odometry_timeout_s, def.odometry_timeout_s);
  }
  // A missing vehicle file names the key and the file.
  std::ifstream in(src + "/config/guidance/otter.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.rfind("config/vehicles/otter.yaml");  // the key, not the header
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::strlen("config/vehicles/otter.yaml"), "config/vehicles/nope.yaml");
  const auto bad = config::Value::parse(text, src + "/config/guidance/g.yaml");
  try {
    load_follower_node_params(bad);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("g.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("braking_decel.vehicle_file"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("not found: config/vehicles/nope.yaml"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tiller::guidance
