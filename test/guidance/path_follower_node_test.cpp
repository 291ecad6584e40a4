// The path follower node: messages in, setpoint / progress / station target out; bad input
// (table-driven: a malformed message of each input type is dropped, counted, and changes no
// output); a cancel over the bus after a path is obeyed; the operator's pause, resume, abort.
#include <gtest/gtest.h>

#include <tiller/mission_command_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include <cmath>
#include <functional>
#include <set>
#include <vector>

#include "bad_values.hpp"
#include "core/config.hpp"
#include "guidance/path_follower_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::guidance {
namespace {

FollowerNodeParams params() {
  return load_follower_node_params(
      config::Value::load_file(std::string(TILLER_SOURCE_DIR) + "/config/guidance/default.yaml"));
}

odometry_t odom(TimeUs t, double n, double e, double psi) {
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  o.utime = t;
  o.position[0] = n;
  o.position[1] = e;
  o.orientation[2] = psi;
  return o;
}

path_t path(std::int64_t id, std::initializer_list<std::pair<double, double>> l) {
  path_t p{};
  p.path_id = id;
  for (auto [n, e] : l) {
    waypoint_t w{};
    w.position[0] = n;
    w.position[1] = e;
    p.waypoints.push_back(w);
  }
  p.n_waypoints = static_cast<std::int32_t>(p.waypoints.size());
  return p;
}

struct Seen {
  velocity_setpoint_t sp{};
  path_progress_t pr{};
  station_target_t st{};
  int n_sp = 0;
};

void watch(LockstepExecutor& ex, Seen& s) {
  ex.observe([&s](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == channels::kVelocitySetpoint) {
      s.sp.decode(d, 0, n);
      ++s.n_sp;
    }
    if (ch == channels::kPathProgress) s.pr.decode(d, 0, n);
    if (ch == channels::kStationTarget) s.st.decode(d, 0, n);
  });
}

TEST(PathFollowerNode, FollowsAndCompletes) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kOdometry, odom(0, 0, 0, 0), 50'000);
  ex.inject(channels::kPath, path(7, {{0, 0}, {10, 0}}), 60'000);
  ex.inject(channels::kOdometry, odom(100'000, 5, 0, 0), 150'000);
  ex.run_until(200'000);
  EXPECT_TRUE(s.sp.active);
  EXPECT_EQ(s.sp.frame, velocity_setpoint_t::FRAME_NED);
  EXPECT_NEAR(s.sp.velocity[0], 1.5, 1e-9);
  EXPECT_EQ(s.pr.path_id, 7);
  EXPECT_EQ(s.pr.segment, 0);
  EXPECT_NEAR(s.pr.distance_to_goal, 5.0, 1e-9);
  EXPECT_FALSE(s.st.active);
  ex.inject(channels::kOdometry, odom(250'000, 9.6, 0.1, 0), 250'000);
  ex.run_until(300'000);
  EXPECT_TRUE(s.pr.complete);
  EXPECT_TRUE(s.st.active);
  EXPECT_DOUBLE_EQ(s.st.position[0], 10.0);
  EXPECT_FALSE(s.st.heading_valid);
}

TEST(PathFollowerNode, BadInputIsDroppedAndCounted) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kOdometry, odom(0, 0, 0, 0), 10'000);
  auto bad = path(1, {{0, 0}, {NAN, 3}});
  ex.inject(channels::kPath, bad, 20'000);
  ex.inject(channels::kPath, path(3, {{0, 0}, {2e6, 0}}), 30'000);
  auto nan_odom = odom(40'000, NAN, 0, 0);
  ex.inject(channels::kOdometry, nan_odom, 40'000);
  ex.run_until(100'000);
  EXPECT_EQ(node.counter_value("rejected.path.invalid"), 2);
  EXPECT_EQ(node.counter_value("rejected.odometry.nan"), 1);
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(s.pr.path_id, -1);
  // Repeated points and a single point are followed, not rejected.
  ex.inject(channels::kPath, path(4, {{0, 0}, {0, 0}, {0, 0}}), 110'000);
  ex.run_until(200'000);
  EXPECT_EQ(node.counter_value("rejected.path.invalid"), 2);
  EXPECT_TRUE(s.pr.complete);
  EXPECT_TRUE(s.st.active);
  for (double v : s.sp.velocity) EXPECT_TRUE(std::isfinite(v));
}

TEST(PathFollowerNode, StaleOdometryMakesTheSetpointInactiveWithinItsLimit) {
  auto p = params();
  PathFollowerNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kOdometry, odom(0, 0, 0, 0), 0);
  ex.inject(channels::kPath, path(1, {{0, 0}, {100, 0}}), 0);
  ex.run_until(300'000);
  EXPECT_TRUE(s.sp.active);
  // Last odometry at t = 0; limit 0.5 s; ticks every 0.1 s: inactive from the 0.6 s tick.
  ex.run_until(500'000);
  EXPECT_TRUE(s.sp.active);
  ex.run_until(600'000);
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(node.stale(), 1);
}

// A path, then a cancel (n_waypoints 0), both through the node's subscription (one reused decode
// target): the cancel is obeyed, not refused.
TEST(PathFollowerNode, CancelAfterAPathOverTheBusStopsTheFollower) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kOdometry, odom(0, 0, 0, 0), 0);
  ex.inject(channels::kPath, path(5, {{0, 0}, {100, 0}}), 10'000);
  ex.inject(channels::kOdometry, odom(100'000, 1, 0, 0), 100'000);
  ex.run_until(200'000);
  ASSERT_TRUE(s.sp.active);
  ex.inject(channels::kPath, path(6, {}), 210'000);
  ex.inject(channels::kOdometry, odom(250'000, 1.1, 0, 0), 250'000);
  ex.run_until(300'000);
  EXPECT_EQ(node.counter_value("rejected.path.invalid"), 0);
  EXPECT_EQ(node.rejected(), 0);
  EXPECT_FALSE(node.follower().has_path());
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(s.pr.path_id, -1);
}

mission_command_t command(std::int64_t id, std::int8_t c) {
  mission_command_t m{};
  m.command_id = id;
  m.command = c;
  m.source = "test";
  return m;
}

// The operator's PAUSE / RESUME / ABORT (and a cancel) against a path repeated every 0.5 s, as
// tiller-mission repeats its path: a paused path is kept (progress: its id, segment -1, setpoint
// inactive) and RESUME follows it again; an aborted or cancelled path stays dropped when its
// repeats arrive (counted in paths.dropped_repeats), a new path_id starts; a repeated command id
// is ignored.
TEST(PathFollowerNode, PauseResumeAbortAndCancelAgainstARepeatedPath) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  for (TimeUs t = 0; t < 6'000'000; t += 100'000) {
    ex.inject(channels::kOdometry, odom(t, 1, 0, 0), t);
    if (t % 500'000 == 0) ex.inject(channels::kPath, path(5, {{0, 0}, {100, 0}}), t + 10'000);
  }
  ex.run_until(900'000);
  ASSERT_TRUE(s.sp.active);
  ex.inject(channels::kMissionCommand, command(11, mission_command_t::PAUSE), 950'000);
  ex.run_until(1'900'000);  // two repeats of path 5 meanwhile
  EXPECT_TRUE(node.paused());
  EXPECT_TRUE(node.follower().has_path());
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(s.pr.path_id, 5);
  EXPECT_EQ(s.pr.segment, -1);
  EXPECT_FALSE(s.st.active);
  ex.inject(channels::kMissionCommand, command(12, mission_command_t::RESUME), 1'950'000);
  ex.run_until(2'900'000);
  EXPECT_FALSE(node.paused());
  EXPECT_TRUE(s.sp.active);
  EXPECT_EQ(s.pr.segment, 0);
  ex.inject(channels::kMissionCommand, command(12, mission_command_t::PAUSE), 2'950'000);
  ex.run_until(3'000'000);
  EXPECT_FALSE(node.paused());  // id 12 was used: ignored
  ex.inject(channels::kMissionCommand, command(13, mission_command_t::ABORT), 3'050'000);
  ex.run_until(4'900'000);  // three repeats of path 5: 3.51, 4.01, 4.51 s
  EXPECT_FALSE(node.follower().has_path());
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(s.pr.path_id, -1);
  EXPECT_EQ(node.counter_value("paths.dropped_repeats"), 3);
  ex.inject(channels::kPath, path(8, {{0, 0}, {0, 50}}), 4'950'000);  // a new path starts
  ex.run_until(5'100'000);
  EXPECT_TRUE(s.sp.active);
  EXPECT_EQ(s.pr.path_id, 8);
  ex.inject(channels::kPath, path(9, {}), 5'150'000);  // a planner's cancel of path 8
  ex.inject(channels::kPath, path(8, {{0, 0}, {0, 50}}), 5'250'000);
  ex.run_until(5'600'000);
  EXPECT_FALSE(node.follower().has_path());
  EXPECT_EQ(node.counter_value("paths.dropped_repeats"), 6);  // 5 at 5.01, 8 at 5.25, 5 at 5.51 s
}

// ---- Malformed input, table-driven. A reference run (odometry at 20 Hz moving along a path,
// the mode) and, per case, the same run with one malformed message added at 0.525 s: it is
// counted (its counter and rejected() both 1) and every message on the node's output channels
// is byte-identical to the reference run's.
constexpr TimeUs kBadAt = 525'000;
constexpr TimeUs kEnd = 1'500'000;
constexpr double kPi = 3.14159265358979323846;

using Outputs = std::vector<std::pair<std::string, std::vector<std::uint8_t>>>;
using Inject = std::function<void(LockstepExecutor&)>;

template <class Msg>
Inject bad(const std::string& channel, Msg m) {
  return [channel, m](LockstepExecutor& ex) { ex.inject(channel, m, kBadAt); };
}

odometry_t moving(TimeUs t) {
  auto o = odom(t, 0.8 * to_seconds(t), 0.3, 0.1);
  o.velocity[0] = 0.8;
  return o;
}

Outputs run_with(const Inject& extra, std::int64_t* counted, const std::string& counter,
                 std::int64_t* rejected) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  const std::set<std::string> outs = {channels::kVelocitySetpoint, channels::kPathProgress,
                                      channels::kStationTarget};
  Outputs o;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (outs.count(ch)) o.emplace_back(ch, std::vector<std::uint8_t>(d, d + n));
  });
  controller_mode_t m{};
  m.mode = controller_mode_t::WAYPOINTING;
  m.source = "test";
  ex.inject(channels::kMode, m, 0);
  ex.inject(channels::kPath, path(3, {{0, 0}, {20, 0}, {20, 20}}), 0);
  for (TimeUs t = 0; t < kEnd; t += 50'000) ex.inject(channels::kOdometry, moving(t), t);
  if (extra) extra(ex);
  ex.run_until(kEnd);
  if (counted) *counted = node.counter_value(counter);
  if (rejected) *rejected = node.rejected();
  return o;
}

TEST(PathFollowerNode, MalformedInputOfEachTypeIsDroppedCountedAndChangesNothing) {
  const Outputs ref = run_with(nullptr, nullptr, "", nullptr);
  velocity_setpoint_t last{};
  for (const auto& [ch, bytes] : ref)
    if (ch == channels::kVelocitySetpoint)
      last.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
  ASSERT_TRUE(last.active);  // the reference is following the path
  ASSERT_GT(last.velocity[0], 0.5);

  struct BadCase {
    std::string what;
    Inject inject;
    std::string counter;
  };
  auto o = [](auto f) {
    odometry_t m = moving(kBadAt);
    m.position[1] = 5.0;  // accepted, it would move the vehicle off the path
    f(m);
    return bad(channels::kOdometry, m);
  };
  auto wp = [](auto f) {
    path_t p = path(9, {{0, 0}, {0, 20}});  // a new path id: accepted, it would restart
    f(p);
    return bad(channels::kPath, p);
  };
  controller_mode_t bad_mode{};
  bad_mode.mode = 42;  // past DEPTH_HEADING_HOLD (9)
  bad_mode.is_translation = true;
  bad_mode.source = "test";
  // Every bad odometry and path value of test/common/bad_values.hpp, applied to this test's
  // good messages.
  std::vector<BadCase> cases;
  for (const auto& b : test::bad_values<odometry_t>()) {
    cases.push_back({std::string("odometry ") + b.what, o(b.apply),
                     b.kind == test::BadKind::kNonFinite ? "rejected.odometry.nan"
                                                         : "rejected.odometry.range"});
  }
  for (const auto& b : test::bad_values<path_t>())
    cases.push_back({std::string("path ") + b.what, wp(b.apply), "rejected.path.invalid"});
  cases.push_back({"odometry roll 3.5 rad", o([](odometry_t& m) { m.orientation[0] = 3.5; }),
                   "rejected.odometry.range"});
  cases.push_back({"path of 10001 waypoints", wp([](path_t& p) {
                     p.waypoints.resize(10001);
                     p.n_waypoints = 10001;
                   }),
                   "rejected.path.invalid"});
  cases.push_back({"mode unknown", bad(channels::kMode, bad_mode), "rejected.mode.invalid"});

  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    std::int64_t counted = -1, rejected = -1;
    const Outputs got = run_with(c.inject, &counted, c.counter, &rejected);
    EXPECT_EQ(counted, 1);
    EXPECT_EQ(rejected, 1);
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      ASSERT_EQ(got[i], ref[i]) << "output " << i << " on " << ref[i].first << " differs";
    }
  }
}

// Odometry flagged without a valid position (tiller-nav past its limit, or no position
// source) is not followed on: the setpoint goes inactive once the last valid one is stale.
TEST(PathFollowerNode, OdometryWithoutAValidPositionIsStale) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kPath, path(7, {{0, 0}, {100, 0}}), 10'000);
  for (TimeUs t = 20'000; t < 2'000'000; t += 50'000) {
    odometry_t o = odom(t, 0.5 * to_seconds(t), 0, 0);
    if (t >= 1'000'000) o.valid = int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH};
    ex.inject(channels::kOdometry, o, t);
  }
  ex.run_until(900'000);
  EXPECT_TRUE(s.sp.active);
  ex.run_until(1'900'000);
  EXPECT_FALSE(s.sp.active);
  EXPECT_EQ(node.counter_value("odometry.invalid"), 18);  // 1.02 .. 1.87 s
  EXPECT_EQ(node.rejected(), 0);
}

// Issue 31, case 6 (the policy's first step): in a GNSS outage (DEAD_RECKONING) the setpoint is
// the one from before it for outage_hold_course_s (5 s), however the dead-reckoned position
// drifts; then the path is followed on the estimate again.
TEST(PathFollowerNode, AnOutageHoldsTheCourseAndSpeedThenFollowsTheEstimate) {
  PathFollowerNode node(params());
  LockstepExecutor ex(0);
  ex.add(node);
  Seen s;
  watch(ex, s);
  ex.inject(channels::kPath, path(3, {{0, 0}, {100, 0}}), 10'000);
  // On the line, heading north: the setpoint is 1.5 m/s north.
  for (TimeUs t = 0; t <= 1'000'000; t += 100'000)
    ex.inject(channels::kOdometry, odom(t, 1.5e-6 * t, 0, 0), t);
  ex.run_until(1'000'000);
  ASSERT_TRUE(s.sp.active);
  const double vn = s.sp.velocity[0], ve = s.sp.velocity[1];
  EXPECT_NEAR(vn, 1.5, 1e-9);
  // The outage: the estimate drifts 5 m east over 5 s (a follower on it would steer west).
  for (TimeUs t = 1'100'000; t <= 9'000'000; t += 100'000) {
    odometry_t o = odom(t, 1.5e-6 * t, 1e-6 * (t - 1'000'000), 0);
    o.valid |= odometry_t::DEAD_RECKONING;
    ex.inject(channels::kOdometry, o, t);
  }
  ex.run_until(5'900'000);  // 4.8 s into it
  EXPECT_DOUBLE_EQ(s.sp.velocity[0], vn);
  EXPECT_DOUBLE_EQ(s.sp.velocity[1], ve);
  EXPECT_TRUE(node.holding_course(5'900'000));
  EXPECT_EQ(node.counter_value("outages"), 1);
  ex.run_until(6'500'000);  // 5.4 s into it: following the estimate again
  EXPECT_FALSE(node.holding_course(6'500'000));
}

}  // namespace
}  // namespace tiller::guidance
