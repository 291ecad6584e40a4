// The path follower node: messages in, setpoint / progress / station target out; bad input.
#include <gtest/gtest.h>

#include <tiller/path_progress_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include <cmath>

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

}  // namespace
}  // namespace tiller::guidance
