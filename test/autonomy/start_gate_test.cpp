// The mission's start gate (mission/start_gate.hpp): the horizontal 1-sigma against hand-computed
// eigenvalues, each reason the gate stays shut, the settle time to the microsecond, and
// tiller-mission's node publishing nothing (no path, no arm request) until the estimate is good.
#include <gtest/gtest.h>

#include <tiller/arm_state_t.hpp>
#include <tiller/heartbeat_t.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mission/start_gate.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::mission {
namespace {

constexpr std::int32_t kGood = int{odometry_t::VALID_POSITION} | int{odometry_t::VALID_VELOCITY} |
                               int{odometry_t::VALID_ATTITUDE};

// Odometry stamped `t` with the north-east covariance [[nn ne] [ne ee]] (m^2).
odometry_t odom(TimeUs t, double nn, double ee, double ne = 0, std::int32_t valid = kGood) {
  odometry_t o{};
  o.utime = t;
  o.valid = valid;
  o.n_pose_cov = 36;
  o.pose_covariance.assign(36, 0.0);
  o.pose_covariance[0] = nn;
  o.pose_covariance[7] = ee;
  o.pose_covariance[1] = o.pose_covariance[6] = ne;
  o.n_velocity_cov = 0;
  return o;
}

TEST(StartGate, HorizontalStdIsTheLargerEigenvaluesRoot) {
  // diag(4, 1): 2 m. [[2.5 1.5] [1.5 2.5]]: eigenvalues 4 and 1: 2 m. [[3 0] [0 3]]: sqrt 3.
  EXPECT_DOUBLE_EQ(StartGate::horizontal_std(odom(0, 4, 1).pose_covariance.data()), 2.0);
  EXPECT_DOUBLE_EQ(StartGate::horizontal_std(odom(0, 1, 4).pose_covariance.data()), 2.0);
  EXPECT_NEAR(StartGate::horizontal_std(odom(0, 2.5, 2.5, 1.5).pose_covariance.data()), 2.0, 1e-15);
  EXPECT_DOUBLE_EQ(StartGate::horizontal_std(odom(0, 3, 3).pose_covariance.data()), std::sqrt(3.0));
  // [[0.09 -0.04] [-0.04 0.09]]: eigenvalues 0.13 and 0.05.
  EXPECT_NEAR(StartGate::horizontal_std(odom(0, 0.09, 0.09, -0.04).pose_covariance.data()),
              std::sqrt(0.13), 1e-15);
}

TEST(StartGate, DisabledIsAlwaysOpen) {
  StartGate g(StartGateParams{});
  EXPECT_TRUE(g.open(0));
  EXPECT_STREQ(g.why(0), "");
}

TEST(StartGate, OpensAfterTheSettleTimeOfGoodOdometryAndSaysWhyNotBefore) {
  StartGateParams p;
  p.enabled = true;
  p.max_position_std_m = 0.5;
  p.settle_s = 2.0;
  StartGate g(p);
  EXPECT_FALSE(g.open(0));
  EXPECT_STREQ(g.why(0), "no odometry yet");
  TimeUs t = 0;
  const auto feed = [&](double nn, std::int32_t valid, TimeUs until) {
    for (; t <= until; t += 20'000) g.on_odometry(odom(t, nn, nn, 0, valid), t);
    t -= 20'000;
  };
  feed(0.25, odometry_t::VALID_ATTITUDE, 1'000'000);  // position not valid yet
  EXPECT_FALSE(g.open(t));
  EXPECT_STREQ(g.why(t), "the estimate is not valid (position, velocity and attitude)");
  t += 20'000;
  feed(1.5129, kGood, 3'000'000);  // 1.23 m
  EXPECT_FALSE(g.open(t));
  EXPECT_STREQ(g.why(t), "position 1-sigma 1.23 m > 0.50 m");
  EXPECT_NEAR(g.position_std(), 1.23, 1e-12);
  t += 20'000;
  feed(0.25, kGood | odometry_t::DEAD_RECKONING, 3'500'000);  // 0.5 m, but no fix
  EXPECT_STREQ(g.why(t), "the estimate is dead reckoning (no position fix)");
  t += 20'000;
  const TimeUs good_from = t;  // 3.52 s: 0.5 m is within 0.5 m
  feed(0.25, kGood, good_from + 1'000'000);
  EXPECT_FALSE(g.open(t));
  EXPECT_STREQ(g.why(t), "settling: good for 1.0 of 2.0 s");
  t += 20'000;
  feed(0.25, kGood, good_from + 1'980'000);
  EXPECT_FALSE(g.open(good_from + 1'999'999));
  EXPECT_TRUE(g.open(good_from + 2'000'000));
  EXPECT_STREQ(g.why(good_from + 2'000'000), "");
  // The odometry stops: stale 0.5 s after the last sample.
  EXPECT_TRUE(g.open(t + 500'000));
  EXPECT_FALSE(g.open(t + 500'001));
  EXPECT_STREQ(g.why(t + 500'001), "the odometry is stale");
  // Back after a gap: the settle starts again from the first sample after it.
  const TimeUs back = t + 700'000;
  g.on_odometry(odom(back, 0.25, 0.25), back);
  EXPECT_FALSE(g.open(back));
  g.on_odometry(odom(back + 400'000, 0.25, 0.25), back + 400'000);
  EXPECT_FALSE(g.open(back + 400'000));
}

TEST(StartGate, TruthWithoutACovarianceIsTakenAtItsValidityBits) {
  StartGateParams p;
  p.enabled = true;
  StartGate g(p);
  odometry_t o = odom(0, 0, 0);
  o.n_pose_cov = 0;
  o.pose_covariance.clear();
  g.on_odometry(o, 0);
  EXPECT_TRUE(g.open(0));
  EXPECT_EQ(g.position_std(), 0.0);
}

struct Seen {
  std::vector<std::string> channels;
  std::string status;
};

TEST(MissionNodeStartGate, PublishesNothingUntilTheEstimateIsGoodThenThePathAndArmRequest) {
  const auto m =
      load_mission_file(std::string(TILLER_SOURCE_DIR) + "/config/missions/default.yaml");
  StartGateParams p;
  p.enabled = true;
  p.max_position_std_m = 0.5;
  p.settle_s = 1.0;
  MissionNode node(m, 5, kUsPerSecond, true, p);
  LockstepExecutor ex(0);
  ex.add(node);
  Seen seen;
  heartbeat_t hb;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == node.heartbeat_channel()) {
      if (hb.decode(d, 0, n) == n) seen.status = hb.status;
    } else if (ch != channels::kOdometry && ch != channels::kArmState) {
      seen.channels.push_back(ch);
    }
  });
  arm_state_t st{};  // tiller-esc's, for its boot nonce (the arm request waits for one)
  st.reason = "disarmed at start";
  ex.inject(channels::kArmState, st, 0);
  // 0 to 5 s: position 1-sigma 1 m; 5 to 10 s: 0.4 m but one NaN sample, refused and counted.
  for (TimeUs t = 0; t < 10'000'000; t += 20'000) {
    odometry_t o = odom(t, t < 5'000'000 ? 1.0 : 0.16, t < 5'000'000 ? 1.0 : 0.16);
    if (t == 6'000'000) o.position[0] = std::numeric_limits<double>::quiet_NaN();
    ex.inject(channels::kOdometry, o, t);
  }
  ex.run_until(4'500'000);
  EXPECT_TRUE(seen.channels.empty());
  EXPECT_EQ(seen.status, "waiting for the estimate: position 1-sigma 1.00 m > 0.50 m");
  EXPECT_EQ(node.began_at(), -1);
  // Good from 5.0 s: the gate opens at 6.0 s, the node's tick at 6 s publishes (the NaN sample
  // at 6.0 s comes after the tick and changes nothing).
  ex.run_until(6'500'000);
  EXPECT_EQ(node.began_at(), 6'000'000);
  ASSERT_EQ(seen.channels.size(), 3u);
  EXPECT_EQ(seen.channels[0], channels::kPath);
  EXPECT_EQ(seen.channels[1], channels::kMode);
  EXPECT_EQ(seen.channels[2], channels::kArmRequest);
  EXPECT_EQ(seen.status, "publishing " + m.name);
  EXPECT_EQ(node.counter_value("rejected.odometry.invalid"), 1);
}

}  // namespace
}  // namespace tiller::mission
