// Corners along an arc (guidance/turn_arc.hpp, PathFollower with turn_arc): the fillet's
// geometry and the follower's commands on it, against hand-computed values.
#include <gtest/gtest.h>

#include <cmath>

#include "core/angles.hpp"
#include "guidance/path_follower.hpp"
#include "guidance/pivot_turn.hpp"
#include "guidance/turn_arc.hpp"

namespace tiller::guidance {
namespace {

// A right turn (north, then east) at (100, 0) with R = 2: L = R tan 45 deg = 2, the arc from
// (98, 0) to (100, 2) about (98, 2), passing R (sqrt 2 - 1) = 0.828 m inside the corner.
TEST(TurnArc, FilletOfARightAngle) {
  const TurnArc a = make_turn_arc({100, 0}, {1, 0}, {0, 1}, 2.0);
  ASSERT_TRUE(a.valid);
  EXPECT_DOUBLE_EQ(a.sign, 1.0);
  EXPECT_NEAR(a.lead, 2.0, 1e-12);
  EXPECT_NEAR((a.start - Vec2(98, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((a.end - Vec2(100, 2)).norm(), 0, 1e-12);
  EXPECT_NEAR((a.centre - Vec2(98, 2)).norm(), 0, 1e-12);
  EXPECT_NEAR((Vec2(100, 0) - a.centre).norm() - a.radius, 2 * (std::sqrt(2.0) - 1), 1e-12);
  const ArcPosition s = locate(a, {98, 0});
  EXPECT_NEAR(s.outside, 0, 1e-12);
  EXPECT_NEAR((s.tangent - Vec2(1, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((s.inward - Vec2(0, 1)).norm(), 0, 1e-12);
  EXPECT_FALSE(s.past_end);
  const double h = std::sqrt(0.5);
  const ArcPosition m = locate(a, Vec2(98, 2) + 2.5 * Vec2(h, -h));  // 0.5 m outside, halfway
  EXPECT_NEAR(m.outside, 0.5, 1e-12);
  EXPECT_NEAR((m.tangent - Vec2(h, h)).norm(), 0, 1e-12);
  EXPECT_TRUE(locate(a, {100.1, 2.5}).past_end);
  // A left turn (north, then west) mirrors it; straight on and hairpins have no arc.
  const TurnArc l = make_turn_arc({100, 0}, {1, 0}, {0, -1}, 2.0);
  EXPECT_DOUBLE_EQ(l.sign, -1.0);
  EXPECT_NEAR((l.centre - Vec2(98, -2)).norm(), 0, 1e-12);
  EXPECT_NEAR((locate(l, {98, 0}).tangent - Vec2(1, 0)).norm(), 0, 1e-12);
  EXPECT_FALSE(make_turn_arc({100, 0}, {1, 0}, {1, 0}, 2.0).valid);
  EXPECT_FALSE(make_turn_arc({100, 0}, {1, 0}, {-1, 0.1}, 2.0).valid);
}

// The follower on (0,0) -> (100,0) -> (100,100), seed law, turn_rate 0.25 rad/s, the arc at most
// 0.5 m inside. The turn's speed 1.5 (1 - 0.8 / 2) = 0.9 m/s gives R = 3.6 m, 1.49 m inside: too
// far, so R = 0.5 / (sqrt 2 - 1) = 1.2071 m and U = R * 0.25 = 0.3018 m/s; the segment is left
// 1.2071 m before the corner; on the arc the heading leads the course by 0.25 rad/s * 1 s.
TEST(TurnArc, FollowerFliesTheCornerAlongItsArcWithAHeadingLead) {
  FollowerParams p;
  p.turn_rate = 0.25;
  p.turn_arc = true;
  p.turn_arc_inside_max = 0.5;
  p.heading_lead_s = 1.0;
  p.end_slowdown = EndSlowdown::kConstantDecel;
  PathFollower f(p);
  std::vector<Waypoint> w(3);
  w[1].position = {100, 0};
  w[2].position = {100, 100};
  ASSERT_TRUE(f.set_path(w, {0, 0}, 0, false));
  const double r = 0.5 / (std::sqrt(2.0) - 1), u = r * 0.25;
  // 1.5 m before the corner: still on the first leg, already at the arc's speed.
  auto o = f.update({98.5, 0}, 0, 0.1);
  EXPECT_EQ(o.segment, 0);
  EXPECT_FALSE(o.on_arc);
  EXPECT_NEAR(o.wheel_over, r, 1e-9);
  EXPECT_NEAR(o.velocity.x(), u, 1e-9);
  EXPECT_NEAR(o.velocity.y(), 0, 1e-12);
  // Just past the wheel-over point (98.7929): on the arc, the next segment selected.
  o = f.update({98.8, 0}, 0, 0.1);
  EXPECT_EQ(o.segment, 1);
  ASSERT_TRUE(o.on_arc);
  const double course = std::atan2(o.velocity.y(), o.velocity.x());
  EXPECT_NEAR(angle_diff(o.target_heading, course), 0.25, 1e-9);
  EXPECT_NEAR(o.along_speed, u, 1e-9);
  EXPECT_LT(std::abs(course), 0.02);  // along the arc's start: north
  // Halfway round, on the arc, heading along it: the velocity along the tangent (45 deg).
  const double h = std::sqrt(0.5);
  const Vec2 centre(100 - r, r);
  o = f.update(centre + r * Vec2(h, -h), kPi / 4, 0.1);
  ASSERT_TRUE(o.on_arc);
  EXPECT_NEAR(o.velocity.x(), u * h, 1e-9);
  EXPECT_NEAR(o.velocity.y(), u * h, 1e-9);
  EXPECT_NEAR(o.target_heading, kPi / 4 + 0.25, 1e-9);
  // Past the arc's end: the second leg as usual (no lead).
  o = f.update({100, r + 0.5}, kPi / 2, 0.1);
  EXPECT_FALSE(o.on_arc);
  EXPECT_EQ(o.segment, 1);
  EXPECT_NEAR(angle_diff(o.target_heading, std::atan2(o.velocity.y(), o.velocity.x())), 0, 1e-12);
}

// In still water the water turn is the fillet: a 90 deg turn at 0.3 m/s and 0.25 rad/s is the
// arc of radius 1.2 m, started 1.2 m before the corner, ending 1.2 m along the next leg.
TEST(WaterTurn, InStillWaterItIsTheFillet) {
  const Vec2 t1(0, 1), t2(1, 0);  // east, then north: a left turn
  const WaterTurn w = plan_water_turn(t1, t2, {0, 0}, 0.3, 0.25);
  ASSERT_TRUE(w.valid);
  EXPECT_NEAR(w.dpsi, -kPi / 2, 1e-12);
  EXPECT_NEAR(w.duration, 2 * kPi, 1e-9);
  EXPECT_NEAR(w.lead, 1.2, 1e-3);
  EXPECT_NEAR(w.displacement.x(), 1.2, 1e-3);  // north
  EXPECT_NEAR(w.displacement.y(), 1.2, 1e-3);  // east
}

// A current along the first leg (0.2 m/s east): the turn through the water is the same, the
// boat carried 0.2 m/s east for its duration, so it starts that much earlier; the leg's ground
// speed is the water speed plus the current along it.
TEST(WaterTurn, ACurrentAlongTheLegMovesTheWheelOver) {
  const Vec2 t1(0, 1), t2(1, 0);
  const WaterTurn w = plan_water_turn(t1, t2, {0, 0.2}, 0.3, 0.25);
  ASSERT_TRUE(w.valid);
  EXPECT_NEAR(w.ground1, 0.5, 1e-12);
  EXPECT_NEAR(w.ground2, 0.3, 1e-12);
  // Ends on the outgoing line: the start (-lead along t1) plus the displacement has no east part.
  EXPECT_NEAR((-t1 * w.lead + w.displacement).y(), 0, 1e-9);
  EXPECT_GT(w.lead, 1.2 + 0.2 * 0.5 * w.duration);
  EXPECT_NEAR(ground_offset(w, w.duration).x(), w.displacement.x(), 1e-12);
}

// The current along a leg (observe_current_along): replaces the estimate's part along the leg,
// only in the leg's middle and with the heading near the leg's.
TEST(WaterTurn, TheCurrentAlongALegIsTakenInTheLegsMiddle) {
  FollowerParams p;
  p.law = CrossTrackLaw::kWorldIntegral;
  PathFollower f(p);
  ASSERT_TRUE(f.set_path({{{0, 0}}, {{0, 200}}, {{150, 200}}}, {0, 0}, kPi / 2, false));
  f.update({0, 5}, kPi / 2, 0.1);
  f.observe_current_along(kPi / 2, 0.2);  // 5 m in: not yet
  EXPECT_NEAR(f.current_full().y(), 0, 1e-12);
  f.update({0, 100}, kPi / 2, 0.1);
  f.observe_current_along(0, 0.2);  // heading 90 deg off the leg: not taken
  EXPECT_NEAR(f.current_full().y(), 0, 1e-12);
  f.observe_current_along(kPi / 2, 0.2);
  EXPECT_NEAR(f.current_full().y(), 0.2, 1e-12);
  EXPECT_NEAR(f.current_full().x(), 0, 1e-12);
}

// The pivot's drift (pivot_turn.hpp): for a 90 deg turn D = (pi / 4 c1 - c2 / 2) / r, c1 and c2
// the current along the incoming and outgoing legs.
TEST(PivotTurn, TheDriftOfANinetyDegreeTurnIsQuarterPiC1LessHalfC2OverTheRate) {
  const Vec2 east(0, 1), north(1, 0);
  const Vec2 c(0.15, 0.26);  // toward 60 deg: 0.26 along the eastward leg, 0.15 along north
  const double d = pivot_drift(east, north, c, 0.3);
  EXPECT_NEAR(d, (kPi / 4 * 0.26 - 0.15 / 2) / 0.3, 2e-3);  // 0.4307 m outward
  // The other way round (a right turn, north to east): c1 = 0.15, c2 = 0.26.
  EXPECT_NEAR(pivot_drift(north, east, c, 0.3), (kPi / 4 * 0.15 - 0.26 / 2) / 0.3, 2e-3);
  EXPECT_EQ(pivot_drift(east, north, Vec2(0, 0), 0.3), 0.0);
  EXPECT_EQ(pivot_drift(east, north, c, 0.0), 0.0);
  // The setback: the drift less the allowance, within [0, max_offset].
  EXPECT_NEAR(pivot_setback(east, north, c, 0.3, 0.1, 0.8), d - 0.1, 1e-12);
  EXPECT_EQ(pivot_setback(east, north, c, 0.3, 0.1, 0.2), 0.2);
  EXPECT_EQ(pivot_setback(north, east, c, 0.3, 0.1, 0.8), 0.0);  // the drift is inward
}

}  // namespace
}  // namespace tiller::guidance
