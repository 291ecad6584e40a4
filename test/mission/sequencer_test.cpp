// mission::Sequencer on hand-built missions in metres: the legs, speeds, loiter times, jump
// repeats, return home (to the nearest rally point), stop, and the run-time fence's actions.
#include <gtest/gtest.h>

#include "mission/fence.hpp"
#include "mission/sequencer.hpp"

namespace tiller::mission {
namespace {

using Action = Sequencer::Action;
using State = Sequencer::State;

MissionPoint pt(double n, double e) {
  MissionPoint p;
  p.north = n;
  p.east = e;
  return p;
}
Item wp(double n, double e, ItemKind k = ItemKind::kWaypoint) {
  Item it;
  it.kind = k;
  it.has_point = true;
  it.point = pt(n, e);
  return it;
}
Item loiter(double n, double e, double s) {
  Item it = wp(n, e, ItemKind::kLoiter);
  it.loiter_s = s;
  return it;
}
Item speed(double v) {
  Item it;
  it.kind = ItemKind::kSpeed;
  it.speed = v;
  return it;
}
Item jump(int to, int repeat) {
  Item it;
  it.kind = ItemKind::kJump;
  it.jump_to = to;
  it.repeat = repeat;
  return it;
}
Item simple(ItemKind k) {
  Item it;
  it.kind = k;
  return it;
}

void expect_points(const Leg& leg, std::initializer_list<std::pair<double, double>> pts) {
  ASSERT_EQ(leg.points.size(), pts.size());
  std::size_t k = 0;
  for (const auto& [n, e] : pts) {
    EXPECT_DOUBLE_EQ(leg.points[k].north, n) << k;
    EXPECT_DOUBLE_EQ(leg.points[k].east, e) << k;
    ++k;
  }
}

TEST(Sequencer, LoiterJumpSpeedReturnHome) {
  Mission m;
  m.items = {wp(10, 0),
             speed(0.5),
             wp(10, 10),
             loiter(0, 10, 5),
             wp(0, 0),
             jump(0, 1),
             simple(ItemKind::kReturnHome)};
  m.home_point = pt(-2, -1);
  Sequencer s(m);
  ASSERT_EQ(s.begin(pt(1, 1), 0), Action::kNewLeg);
  expect_points(s.leg(), {{1, 1}, {10, 0}, {10, 10}, {0, 10}});
  // From the speed item on: the segment from (10, 0) and every one after it.
  EXPECT_EQ(s.leg().speeds, (std::vector<double>{0, 0.5, 0.5, 0.5}));
  EXPECT_EQ(s.on_tick(from_seconds(3)), Action::kNone);  // not at the loiter yet
  EXPECT_EQ(s.on_leg_complete(from_seconds(20)), Action::kNone);
  EXPECT_EQ(s.state(), State::kLoitering);
  EXPECT_EQ(s.on_tick(from_seconds(24.9)), Action::kNone);
  ASSERT_EQ(s.on_tick(from_seconds(25)), Action::kNewLeg);  // 5 s after the arrival
  // The jump (once) goes back to item 0 within the leg, at the speed in force.
  expect_points(s.leg(), {{0, 10}, {0, 0}, {10, 0}, {10, 10}, {0, 10}});
  EXPECT_EQ(s.leg().speeds, (std::vector<double>{0.5, 0.5, 0.5, 0.5, 0.5}));
  EXPECT_EQ(s.leg_number(), 2);
  EXPECT_EQ(s.on_leg_complete(from_seconds(60)), Action::kNone);
  ASSERT_EQ(s.on_tick(from_seconds(65)), Action::kNewLeg);
  expect_points(s.leg(), {{0, 10}, {0, 0}, {-2, -1}});  // the jump used up; home
  EXPECT_EQ(s.on_leg_complete(from_seconds(80)), Action::kNone);
  EXPECT_EQ(s.state(), State::kHolding);
  EXPECT_EQ(s.on_tick(from_seconds(200)), Action::kNone);
}

TEST(Sequencer, ReturnToTheNearestRallyPointThenStop) {
  Mission m;
  m.items = {wp(50, 0), simple(ItemKind::kReturnHome), wp(99, 99)};
  m.rally = {pt(45, 5), pt(-10, 0)};
  m.return_end = ReturnEnd::kStop;
  Sequencer s(m);
  s.begin(pt(0, 0), 0);
  // The leg starts at the vehicle (0, 0): home (0, 0) is nearest to it, 0 m.
  expect_points(s.leg(), {{0, 0}, {50, 0}, {0, 0}});
  EXPECT_EQ(s.on_leg_complete(from_seconds(90)), Action::kStop);  // items after RTL: never
  EXPECT_EQ(s.state(), State::kStopped);
  Mission r = m;
  r.items = {wp(50, 0), loiter(50, 1, 0), simple(ItemKind::kReturnHome)};
  Sequencer t(r);
  t.begin(pt(0, 0), 0);
  t.on_leg_complete(from_seconds(40));
  ASSERT_EQ(t.on_tick(from_seconds(40)), Action::kNewLeg);  // a loiter of 0 s
  expect_points(t.leg(), {{50, 1}, {45, 5}});               // rally (45, 5): 6.4 m, home 50 m
}

TEST(Sequencer, StopWithoutAPointAndLoiterForEver) {
  Mission m;
  m.items = {wp(5, 0), simple(ItemKind::kStop)};
  Sequencer s(m);
  ASSERT_EQ(s.begin(pt(0, 0), 0), Action::kNewLeg);
  expect_points(s.leg(), {{0, 0}, {5, 0}});
  EXPECT_EQ(s.on_leg_complete(1), Action::kStop);
  Mission f;
  f.items = {loiter(5, 0, -1), wp(9, 9)};
  Sequencer u(f);
  u.begin(pt(0, 0), 0);
  expect_points(u.leg(), {{0, 0}, {5, 0}});
  EXPECT_EQ(u.on_leg_complete(1), Action::kNone);
  EXPECT_EQ(u.state(), State::kHolding);
  EXPECT_EQ(u.on_tick(from_seconds(1e5)), Action::kNone);  // never goes on to (9, 9)
}

TEST(Sequencer, AJumpForEverFliesCappedLegs) {
  Mission m;
  m.items = {wp(5, 0), wp(5, 5), jump(0, -1)};
  Sequencer s(m);
  s.begin(pt(0, 0), 0);
  EXPECT_EQ(s.leg().points.size(), Sequencer::kMaxLegPoints);
  ASSERT_EQ(s.on_leg_complete(1), Action::kNewLeg);
  EXPECT_EQ(s.leg().points.size(), Sequencer::kMaxLegPoints);
  EXPECT_EQ(s.state(), State::kFlying);
}

Mission fenced(FenceAction a) {
  Mission m;
  m.items = {wp(10, 0), wp(10, 10)};
  FenceShape in;
  in.polygon = {pt(-5, -5), pt(-5, 15), pt(15, 15), pt(15, -5)};
  m.fence = {in};
  m.fence_action = a;
  m.home_point = pt(0, 0);
  return m;
}

TEST(Sequencer, TheFenceAtRunTimeHoldsReturnsOrStops) {
  {
    const Mission m = fenced(FenceAction::kHold);
    Sequencer s(m);
    EXPECT_EQ(s.on_position(20, 0, 0), Action::kNone);  // not started: nothing to act on
    s.begin(pt(0, 0), 0);
    EXPECT_EQ(s.on_position(14.9, 0, 1), Action::kNone);
    EXPECT_EQ(s.on_position(15.2, 3, 2), Action::kHold);
    EXPECT_TRUE(s.fence_breached());
    EXPECT_EQ(s.state(), State::kFenceHold);
    EXPECT_EQ(s.status(), "fence: left inclusion polygon 0 at (15.2 m north, 3.0 m east): holding");
    EXPECT_EQ(s.on_position(16, 3, 3), Action::kNone);  // once
    EXPECT_EQ(s.on_leg_complete(4), Action::kNone);     // and the mission does not go on
  }
  {
    const Mission m = fenced(FenceAction::kReturn);
    Sequencer s(m);
    s.begin(pt(0, 0), 0);
    ASSERT_EQ(s.on_position(15.2, 3, 2), Action::kNewLeg);
    expect_points(s.leg(), {{15.2, 3}, {0, 0}});
    EXPECT_EQ(s.on_leg_complete(3), Action::kNone);
    EXPECT_EQ(s.state(), State::kHolding);
  }
  {
    const Mission m = fenced(FenceAction::kNeutral);
    Sequencer s(m);
    s.begin(pt(0, 0), 0);
    EXPECT_EQ(s.on_position(-6, 0, 2), Action::kStop);
    EXPECT_EQ(s.state(), State::kStopped);
  }
}

}  // namespace
}  // namespace tiller::mission
