// The LOS cross-track laws (los, integral ILOS, adaptive ALOS), their state at a segment switch
// and the wheel-over point, against hand-computed values; and issue 13 finding 2 (the old
// world-frame integral correction, never unwound at a corner, pushed the commanded speed above
// max_speed) with a vehicle that does exactly what it is told in a current.
#include <gtest/gtest.h>

#include <cmath>

#include "guidance/path_follower.hpp"

namespace tiller::guidance {
namespace {

FollowerParams los_params(CrossTrackLaw law) {
  FollowerParams p;
  p.max_speed = 1.5;
  p.law = law;
  p.lookahead = 5.0;
  p.integral_kappa = 1.0;
  p.adaptive_gamma = 0.005;
  p.max_crab = 0.5;
  p.integral_zone = 3.0;
  p.turn_rate = 0;
  p.integral_gain = 0.05;
  p.integral_limit = 0.5;
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

// Path north, vehicle 1 m east (e = +1, right of the path), 50 m from the end, heading north.
FollowerOutput one_step(PathFollower& f, double state, double heading, double dt) {
  f.set_path(pts({{0, 0}, {100, 0}}), Vec2(50, 1), heading, false);
  f.set_state(state);
  return f.update(Vec2(50, 1), heading, dt);
}

TEST(LosLaws, PlainLosHeadingAndSpeedAlong) {
  PathFollower f(los_params(CrossTrackLaw::kLos));
  const auto o = one_step(f, 0, 0, 0.1);
  EXPECT_DOUBLE_EQ(o.cross_track, 1.0);
  EXPECT_NEAR(o.target_heading, -std::atan(1.0 / 5.0), 1e-12);  // -0.19740 rad
  // Speed max_speed along that heading, reduced by the heading error (0.1974 / (pi/2)).
  const double factor = 1 - std::atan(0.2) / (kPi / 2);
  EXPECT_NEAR(o.velocity.norm(), 1.5 * factor, 1e-12);
  EXPECT_NEAR(std::atan2(o.velocity.y(), o.velocity.x()), -std::atan(0.2), 1e-12);
  // Already on that heading: the full max_speed, never more, even 10 m off the path.
  EXPECT_NEAR(one_step(f, 0, -std::atan(0.2), 0.1).velocity.norm(), 1.5, 1e-12);
  f.set_path(pts({{0, 0}, {100, 0}}), Vec2(50, 10), 0, false);
  const auto far = f.update(Vec2(50, 10), -std::atan(2.0), 0.1);
  EXPECT_NEAR(far.target_heading, -std::atan(2.0), 1e-12);
  EXPECT_NEAR(far.velocity.norm(), 1.5, 1e-12);
}

TEST(LosLaws, IntegralLosHandComputed) {
  PathFollower f(los_params(CrossTrackLaw::kIntegral));
  // y_int 0.5: d(y_int)/dt = 5 * 1 / ((1 + 0.5)^2 + 25) = 5 / 27.25; after 0.1 s 0.5183486.
  const auto o = one_step(f, 0.5, 0, 0.1);
  const double y = 0.5 + 0.1 * 5.0 / 27.25;
  EXPECT_NEAR(f.state(), y, 1e-12);
  EXPECT_NEAR(o.target_heading, -std::atan((1.0 + y) / 5.0), 1e-12);  // -0.29482 rad
  EXPECT_NEAR(o.crab, std::atan(y / 5.0), 1e-12);
  // dt 0: no integration.
  one_step(f, 0.5, 0, 0);
  EXPECT_DOUBLE_EQ(f.state(), 0.5);
  // Bounded: atan(kappa y / Delta) <= max_crab (0.5 rad): y <= 5 tan(0.5) = 2.7315.
  one_step(f, 10, 0, 0.1);
  EXPECT_NEAR(f.state(), 5 * std::tan(0.5), 1e-12);
}

TEST(LosLaws, AdaptiveLosHandComputed) {
  PathFollower f(los_params(CrossTrackLaw::kAdaptive));
  // beta_hat 0.1: d/dt = 0.005 * 5 * 1 / sqrt(26) = 0.0049029; after 0.1 s 0.10049029.
  const auto o = one_step(f, 0.1, 0, 0.1);
  const double b = 0.1 + 0.1 * 0.005 * 5 / std::sqrt(26.0);
  EXPECT_NEAR(f.state(), b, 1e-12);
  EXPECT_NEAR(o.target_heading, -b - std::atan(0.2), 1e-12);  // -0.29789 rad
  EXPECT_NEAR(o.crab, b, 1e-12);
  // Outside integral_zone (3 m): no adaptation.
  f.set_path(pts({{0, 0}, {100, 0}}), Vec2(50, 4), 0, false);
  f.set_state(0.1);
  f.update(Vec2(50, 4), 0, 0.1);
  EXPECT_DOUBLE_EQ(f.state(), 0.1);
}

// At a switch the state's crab angle beta becomes asin(sin(beta) cos(turn)).
double crab_after_switch(CrossTrackLaw law, std::initializer_list<std::pair<double, double>> path,
                         Vec2 at) {
  PathFollower f(los_params(law));
  f.set_path(pts(path), Vec2(0, 0), 0, false);
  f.update(Vec2(50, 0), 0, 0);                                             // on the first leg
  f.set_state(law == CrossTrackLaw::kIntegral ? 5 * std::tan(0.2) : 0.2);  // crab 0.2 rad
  const auto o = f.update(at, 0, 0);
  EXPECT_EQ(o.segment, 1);
  return o.crab;
}

TEST(LosLaws, StateAtASwitchIsProjectedOntoTheNewPathNormal) {
  for (auto law : {CrossTrackLaw::kIntegral, CrossTrackLaw::kAdaptive}) {
    SCOPED_TRACE(static_cast<int>(law));
    // 90 deg: reset.
    EXPECT_NEAR(crab_after_switch(law, {{0, 0}, {100, 0}, {100, 100}}, Vec2(100.2, 0.5)), 0, 1e-12);
    // Hairpin (180 deg, the return leg 0.1 m aside): flipped.
    EXPECT_NEAR(crab_after_switch(law, {{0, 0}, {100, 0}, {0, 0.1}}, Vec2(100.5, 0)),
                std::asin(std::sin(0.2) * std::cos(kPi - std::atan2(0.1, 100))), 1e-12);
    // A 30 deg bend: sin(beta) cos(30 deg).
    const double s30 = std::sin(kPi / 6), c30 = std::cos(kPi / 6);
    EXPECT_NEAR(
        crab_after_switch(law, {{0, 0}, {100, 0}, {100 + 100 * c30, 100 * s30}}, Vec2(100.2, 0)),
        std::asin(std::sin(0.2) * c30), 1e-12);
  }
}

// world_integral at a switch (issue 13 finding 2): 40 steps of 0.1 s 1 m right of the first leg
// (north) build a correction 0.05 * 1 m * 4 s = 0.2 m/s east (toward the path). On a 90 deg
// corner (second leg east) that lies along the new leg: kept whole it added 0.2 m/s to the
// end slow-down's sqrt(2 * 0.25 * 1) = 0.7071 m/s 1 m before the goal (0.9071); projected onto
// the new normal it is zero. On a 30 deg bend its normal component, 0.2 cos 30 deg, stays (the
// velocity there is (along + correction) * the heading factor).
Vec2 world_integral_after_switch(const Vec2& p3, const Vec2& probe) {
  PathFollower f(los_params(CrossTrackLaw::kWorldIntegral));
  f.set_path(pts({{0, 0}, {20, 0}, {p3.x(), p3.y()}}), Vec2(0, 0), 0, false);
  for (int i = 0; i < 40; ++i) f.update(Vec2(10, -1), 0, 0.1);
  EXPECT_EQ(f.update(Vec2(19.5, 0), 0, 0).segment, 1);  // dt 0: no integration on the new leg
  const Vec2 t = (p3 - Vec2(20, 0)).normalized();
  const auto o = f.update(probe, std::atan2(t.y(), t.x()), 0);  // on the leg, heading along it
  EXPECT_LT(o.velocity.norm(), 1.5);                            // below max_speed: not scaled
  EXPECT_NEAR(o.cross_track, 0, 1e-9);
  EXPECT_GT(o.heading_factor, 0.8);
  return o.velocity / o.heading_factor - t * o.along_speed;  // what is left: the correction
}

TEST(LosLaws, WorldIntegralKeepsOnlyTheNewNormalComponentAtASwitch) {
  const Vec2 c90 = world_integral_after_switch(Vec2(20, 20), Vec2(20, 19));
  EXPECT_NEAR(c90.norm(), 0, 1e-12);
  const double s30 = std::sin(kPi / 6), c30 = std::cos(kPi / 6);
  const Vec2 p3(20 + 20 * c30, 20 * s30);
  const Vec2 n(-s30, c30);  // the second leg's normal (left of it)
  const Vec2 c = world_integral_after_switch(p3, p3 - Vec2(c30, s30));  // 1 m before the end
  EXPECT_NEAR(c.dot(n), 0.2 * c30, 1e-12);
  EXPECT_NEAR(c.dot(Vec2(c30, s30)), 0, 1e-12);
}

// The current estimate carried through corners: 40 steps 1 m right of the first leg (north) build
// 0.2 m/s east, which is across the first leg only. After a 90 deg corner (second leg east) none
// of it applies (it lies along the leg: finding 2), but it is kept: after the next corner (third
// leg south) it is across the leg again and applies at once, 0.2 m/s east. Before, the second
// leg's projection dropped it: the third leg started from zero and drifted until it re-learnt it.
TEST(LosLaws, WorldIntegralKeepsWhatALegLearntForTheLegsAcrossIt) {
  PathFollower f(los_params(CrossTrackLaw::kWorldIntegral));
  f.set_path(pts({{0, 0}, {20, 0}, {20, 20}, {0, 20}}), Vec2(0, 0), 0, false);
  for (int i = 0; i < 40; ++i) f.update(Vec2(10, -1), 0, 0.1);
  EXPECT_NEAR(f.current_estimate().y(), -0.2, 1e-12);         // the water sets the boat west
  EXPECT_EQ(f.update(Vec2(20.5, 1), kPi / 2, 0).segment, 1);  // past the corner
  const auto o2 = f.update(Vec2(20, 10), kPi / 2, 0);         // on the second leg, along it
  EXPECT_EQ(o2.segment, 1);
  EXPECT_NEAR(o2.velocity.x(), 0, 1e-12);  // nothing across the leg
  EXPECT_NEAR(o2.velocity.y(), 1.5, 1e-12);
  EXPECT_EQ(f.update(Vec2(19, 20.5), kPi, 0).segment, 2);  // past the second corner
  const auto o3 = f.update(Vec2(10, 20), kPi, 0);          // on the third leg (south)
  EXPECT_EQ(o3.segment, 2);
  // 0.2 m/s east, added to 1.5 south and scaled to max_speed (then by the heading factor).
  EXPECT_NEAR(o3.velocity.y() / o3.heading_factor, 0.2 * 1.5 / std::hypot(1.5, 0.2), 1e-12);
}

// The same for integral and adaptive LOS: the crab held on the first leg returns on the third.
TEST(LosLaws, CrabCarriedThroughTwoCornersComesBackOnTheThirdLeg) {
  for (auto law : {CrossTrackLaw::kIntegral, CrossTrackLaw::kAdaptive}) {
    SCOPED_TRACE(static_cast<int>(law));
    PathFollower f(los_params(law));
    f.set_path(pts({{0, 0}, {100, 0}, {100, 100}, {0, 100}}), Vec2(0, 0), 0, false);
    f.set_state(law == CrossTrackLaw::kIntegral ? 5 * std::tan(0.2) : 0.2);  // crab 0.2 rad
    EXPECT_NEAR(f.update(Vec2(100.2, 0.5), 0, 0).crab, 0, 1e-12);            // 90 deg: none across
    EXPECT_NEAR(f.update(Vec2(99.8, 100.5), kPi, 0).crab, -0.2, 1e-12);  // reversed leg: flipped
  }
}

// With turn_drift_rate, the wheel-over point moves by the drift the current estimate predicts in
// the turn. A first leg east, 1 m south of it for 4 s: 0.2 m/s of current toward the south
// estimated (the correction points north). A second leg north (s = 1) or south (s = -1), then a
// 90 deg corner onto a leg east: the turn's outside is along the second leg, so the current sets
// the boat inward (s = 1: the turn starts 0.2 * (pi / 2) / 0.5 = 0.628 m later) or outward (s = -1:
// as much earlier); bounded by the wheel-over itself.
TEST(LosLaws, WheelOverMovesByTheCurrentsDriftInTheTurn) {
  for (double s : {1.0, -1.0}) {
    SCOPED_TRACE(s);
    auto p = los_params(CrossTrackLaw::kWorldIntegral);
    p.turn_rate = 0.5;
    p.turn_drift_rate = 0.5;
    PathFollower f(p);
    f.set_path(pts({{0, 0}, {0, 40}, {s * 20, 40}, {s * 20, 60}}), Vec2(0, 0), kPi / 2, false);
    for (int i = 0; i < 40; ++i) f.update(Vec2(-1, 10), kPi / 2, 0.1);
    EXPECT_NEAR(f.current_estimate().x(), -0.2, 1e-12);  // m/s: toward the south
    const auto o = f.update(Vec2(s * 10, 40.5), s > 0 ? 0 : kPi, 0);
    EXPECT_EQ(o.segment, 1);
    const double base = f.wheel_over(kPi / 2, 1.5 * f.turn_factor(kPi / 2));
    EXPECT_NEAR(base, 1.8, 1e-12);
    EXPECT_NEAR(o.wheel_over, base - s * 0.2 * (kPi / 2) / 0.5, 1e-9);
  }
}

TEST(LosLaws, WheelOverPointFromTheTurnRadius) {
  auto p = los_params(CrossTrackLaw::kLos);
  p.turn_rate = 0.5;
  p.turn_slowdown_distance = 5.0;
  p.turn_reduction = 0.8;
  p.turn_min_fraction = 0.2;
  PathFollower f(p);
  // 90 deg at the turn's speed 1.5 * (1 - 0.8 / 2) = 0.9 m/s: R = 1.8 m, R tan(45 deg) = 1.8 m.
  EXPECT_NEAR(f.wheel_over(kPi / 2, 0.9), 1.8, 1e-12);
  EXPECT_NEAR(f.wheel_over(kPi / 3, 1.0), 2.0 * std::tan(kPi / 6), 1e-12);
  EXPECT_NEAR(f.wheel_over(kPi, 1.0), 2.0 * std::tan(kPi / 3), 1e-12);  // hairpin: as 120 deg
  f.set_path(pts({{0, 0}, {20, 0}, {20, 20}}), Vec2(0, 0), 0, false);
  const auto before = f.update(Vec2(18.1, 0), 0, 0.1);  // 1.9 m before the corner
  EXPECT_EQ(before.segment, 0);
  EXPECT_NEAR(before.wheel_over, 1.8, 1e-12);
  EXPECT_EQ(f.update(Vec2(18.3, 0), 0, 0.1).segment, 1);  // 1.7 m: the turn begins
  // No turn_rate: the seed's corner cut only (1 m).
  PathFollower g(los_params(CrossTrackLaw::kLos));
  g.set_path(pts({{0, 0}, {20, 0}, {20, 20}}), Vec2(0, 0), 0, false);
  EXPECT_EQ(g.update(Vec2(18.3, 0), 0, 0.1).segment, 0);
  EXPECT_DOUBLE_EQ(g.wheel_over(kPi / 2, 0.9), 0.0);
}

// A vehicle that does exactly what it is told, plus a current; heading = the target.
struct Kinematic {
  double max_speed_seen = 0, cross_track = 0;
};
Kinematic fly(CrossTrackLaw law, const Vec2& current, int steps) {
  auto p = los_params(law);
  PathFollower f(p);
  f.set_path(pts({{0, 0}, {300, 0}, {300, 300}}), Vec2(0, 0), 0, false);
  Vec2 x(0, 0);
  double heading = 0;
  Kinematic k;
  for (int i = 0; i < steps; ++i) {
    const auto o = f.update(x, heading, 0.1);
    if (o.heading_valid) heading = o.target_heading;
    k.max_speed_seen = std::max(k.max_speed_seen, o.velocity.norm());
    k.cross_track = o.cross_track;
    x += (o.velocity + current) * 0.1;
  }
  return k;
}

// Issue 13 finding 2: a 90 deg corner in 0.3 m/s current across the first leg (toward the west,
// so the old law's correction pointed east: along the second leg). The old world-frame integral
// law commanded up to 1.5 + 0.3 m/s after the corner; no law may command above max_speed.
TEST(LosLaws, NoSetpointAboveMaxSpeedAfterACornerInCurrent) {
  // world_integral before the fix: 1.8 m/s, 20 % above max_speed (its correction kept whole
  // across the corner, added to the full along-path speed).
  for (auto law : {CrossTrackLaw::kSeed, CrossTrackLaw::kLos, CrossTrackLaw::kIntegral,
                   CrossTrackLaw::kAdaptive, CrossTrackLaw::kWorldIntegral}) {
    SCOPED_TRACE(static_cast<int>(law));
    const auto k = fly(law, Vec2(0, -0.3), 4000);  // 400 s: both legs
    EXPECT_LE(k.max_speed_seen, 1.5 + 1e-12);
  }
}

// Converged on the second leg in a 0.3 m/s current across it (toward the south): plain LOS keeps
// the offset where sin(atan(e / Delta)) = 0.3 / 1.5, e = 5 tan(asin(0.2)) = 1.0206 m (right of
// the path, the side the current pushes to: e > 0); ILOS and ALOS remove it.
TEST(LosLaws, IntegralAndAdaptiveRemoveTheOffsetOfACrossCurrent) {
  EXPECT_NEAR(fly(CrossTrackLaw::kLos, Vec2(-0.3, 0), 3500).cross_track,
              5 * std::tan(std::asin(0.2)), 0.01);
  EXPECT_LT(std::abs(fly(CrossTrackLaw::kIntegral, Vec2(-0.3, 0), 3500).cross_track), 0.02);
  // ALOS at gamma 0.005 adapts more slowly: 0.085 m after 130 s on the leg (LOS: 1.02 m).
  EXPECT_LT(std::abs(fly(CrossTrackLaw::kAdaptive, Vec2(-0.3, 0), 3500).cross_track), 0.1);
}

}  // namespace
}  // namespace tiller::guidance
