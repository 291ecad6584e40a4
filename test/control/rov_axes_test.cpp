// The ROV modes' per-axis controller (control/rov_axes.hpp) and mode plans
// (control/rov_modes.hpp): hand-computed cases. Closed loop: test/e2e/rov_modes_test.cpp.
#include <gtest/gtest.h>

#include <tiller/controller_mode_t.hpp>

#include <cmath>
#include <string>

#include "control/rov_axes.hpp"
#include "control/rov_config.hpp"
#include "control/rov_modes.hpp"
#include "core/config.hpp"

namespace tiller::control {
namespace {

using M = controller_mode_t;
constexpr AxisRole O = AxisRole::kOff, P = AxisRole::kPilot, R = AxisRole::kRate,
                   H = AxisRole::kHold;

RovAxes make() {
  std::array<RovGains, 6> g{};
  for (auto& x : g) {
    x.pilot = 0.8;
    x.kp = 10;
    x.kd = 2;
    x.ki = 1;
    x.ki_rate = 4;
    x.i_limit = 5;
    x.max_output = 100;
    x.max_rate = 0.5;
    x.capture_rate = 0.05;
  }
  return RovAxes(g, {100, 100, 60, 10, 12, 20}, {90, 90, 50, 10, 11, 20});
}
constexpr std::array<bool, 6> kNone{};

TEST(RovAxes, PilotPassThroughIsAFractionOfTheLayoutsLargestForceThatWay) {
  RovAxes a = make();
  a.set_roles({P, P, P, P, P, P}, false);
  const auto out = a.step({}, {0.5, -0.5, 1, 0, 0, -1}, 0.02, IntegratorRule::kIntegrate, kNone);
  EXPECT_DOUBLE_EQ(out[0], 0.5 * 0.8 * 100);  // 40 N forward
  EXPECT_DOUBLE_EQ(out[1], -0.5 * 0.8 * 90);  // the reverse limit that way
  EXPECT_DOUBLE_EQ(out[2], 1.0 * 0.8 * 60);
  EXPECT_DOUBLE_EQ(out[5], -1.0 * 0.8 * 20);
}

TEST(RovAxes, HoldLawAndItsIntegralByHand) {
  RovAxes a = make();
  a.set_roles({O, O, O, O, H, O}, true);  // pitch held level (target 0 at once)
  ASSERT_TRUE(a.holding(4));
  RovState s;
  s.pitch = 0.1;
  s.nu[4] = 0.2;
  // out = kp e - kd q + I, e = 0 - 0.1; I = ki e dt = -0.002.
  auto out = a.step(s, {}, 0.02, IntegratorRule::kIntegrate, kNone);
  EXPECT_NEAR(a.integral(4), -0.002, 1e-15);
  EXPECT_NEAR(out[4], 10 * -0.1 - 2 * 0.2 - 0.002, 1e-12);
  // Saturated that way at the mixer: the integral does not grow further into it.
  std::array<bool, 6> red{};
  red[4] = true;
  out = a.step(s, {}, 0.02, IntegratorRule::kIntegrate, red);
  EXPECT_NEAR(a.integral(4), -0.002, 1e-15);
  // The gate says frozen: kept; reset (disarmed): zero.
  a.step(s, {}, 0.02, IntegratorRule::kFreeze, kNone);
  EXPECT_NEAR(a.integral(4), -0.002, 1e-15);
  a.step(s, {}, 0.02, IntegratorRule::kReset, kNone);
  EXPECT_EQ(a.integral(4), 0.0);
}

TEST(RovAxes, TheStickOverridesAHoldAndReleaseHoldsTheNewValue) {
  RovAxes a = make();
  a.set_roles({O, O, O, O, O, H}, false);
  RovState s;
  s.yaw = 0.3;
  s.nu[5] = 0.0;
  a.step(s, {}, 0.02, IntegratorRule::kReset, kNone);  // disarmed: the hold follows the vehicle
  EXPECT_TRUE(a.holding(5));
  EXPECT_DOUBLE_EQ(a.target(5), 0.3);
  // Twist at half: a rate law on 0.5 * max_rate = 0.25 rad/s: kd (0.25 - r) + I.
  s.nu[5] = 0.05;
  auto out = a.step(s, {0, 0, 0, 0, 0, 0.5}, 0.02, IntegratorRule::kIntegrate, kNone);
  EXPECT_FALSE(a.holding(5));
  EXPECT_NEAR(a.integral(5), 4 * (0.25 - 0.05) * 0.02, 1e-15);
  EXPECT_NEAR(out[5], 2 * (0.25 - 0.05) + 0.016, 1e-12);
  // Released while still turning: brakes (rate setpoint 0), holds once under capture_rate.
  s.yaw = 0.5;
  s.nu[5] = 0.2;
  a.step(s, {}, 0.02, IntegratorRule::kIntegrate, kNone);
  EXPECT_FALSE(a.holding(5));
  s.yaw = 0.52;
  s.nu[5] = 0.04;
  a.step(s, {}, 0.02, IntegratorRule::kIntegrate, kNone);
  EXPECT_TRUE(a.holding(5));
  EXPECT_DOUBLE_EQ(a.target(5), 0.52);
}

// With max_accel the rate setpoint ramps (both ways: no output step) and a release brakes to
// rest before the value is held, so the target is where the vehicle stopped: a vehicle that
// follows the setpoint exactly is held with no error, and the output changes by at most
// kd * max_accel * dt per step. Without max_accel the release steps the output by kd * rate.
TEST(RovAxes, ARampedReleaseHoldsWhereTheVehicleStops) {
  std::array<RovGains, 6> g{};
  g[5] = {1.0, 10, 1, 2, 4, 5, 100, 0.5, 0.0, 1.5, 0, 1.0};  // yaw: capture at rest, 1 rad/s^2
  RovAxes a(g, {1, 1, 1, 1, 1, 20}, {1, 1, 1, 1, 1, 20});
  a.set_roles({O, O, O, O, O, H}, false);
  RovState s;
  const double dt = 0.02;
  a.step(s, {}, dt, IntegratorRule::kReset, kNone);  // holds 0
  double last = 0, worst = 0;
  auto step = [&](double stick) {
    const double out = a.step(s, {0, 0, 0, 0, 0, stick}, dt, IntegratorRule::kFreeze, kNone)[5];
    worst = std::max(worst, std::fabs(out - last));
    last = out;
    s.nu[5] = a.setpoint(5);  // the vehicle follows the setpoint exactly
    s.yaw += s.nu[5] * dt;
  };
  for (int k = 0; k < 50; ++k) step(1.0);
  EXPECT_NEAR(a.setpoint(5), 0.5, 1e-12);  // 0.02 per step, at max_rate after 25
  const double released = s.yaw;
  for (int k = 0; k < 25; ++k) step(0.0);
  EXPECT_EQ(a.setpoint(5), 0.0);
  EXPECT_FALSE(a.holding(5));  // the rate it measured was still 0.02
  step(0.0);
  ASSERT_TRUE(a.holding(5));
  // It turned 0.02 * (0.48 + 0.46 + ... + 0.02) = 0.12 rad after the release, and is held there.
  EXPECT_NEAR(s.yaw, released + 0.12, 1e-12);
  EXPECT_DOUBLE_EQ(a.target(5), s.yaw);
  EXPECT_LE(worst, 2 * 1.0 * dt + 1e-12);  // kd * max_accel * dt
  step(0.0);
  EXPECT_NEAR(last, 0.0, 1e-12);
  // Without max_accel the same release brakes at once: the output steps by kd * 0.5.
  g[5].max_accel = 0;
  RovAxes b(g, {1, 1, 1, 1, 1, 20}, {1, 1, 1, 1, 1, 20});
  b.set_roles({O, O, O, O, O, H}, false);
  RovState t;
  t.nu[5] = 0.5;
  const double turning = b.step(t, {0, 0, 0, 0, 0, 1}, dt, IntegratorRule::kFreeze, kNone)[5];
  const double braking = b.step(t, {}, dt, IntegratorRule::kFreeze, kNone)[5];
  EXPECT_NEAR(turning - braking, 2 * 0.5, 1e-12);
}

TEST(RovAxes, HeaveActsAlongTheVertical) {
  RovAxes a = make();
  a.set_roles({P, O, R, O, O, O}, false);
  RovState s;
  s.pitch = 0.2;  // nose up: the vertical force has a body X part
  const auto out = a.step(s, {0, 0, 1, 0, 0, 0}, 0, IntegratorRule::kIntegrate, kNone);
  // Rate law: kd (0.5 - depth rate 0) = 1 N down along NED, = R^T [0 0 1] in the body.
  EXPECT_NEAR(a.vertical_force(), 1.0, 1e-12);
  EXPECT_NEAR(out[0], -std::sin(0.2), 1e-12);
  EXPECT_NEAR(out[2], std::cos(0.2), 1e-12);
}

TEST(RovModes, PlansFollowTheLayoutAndRefusalsNameTheAxis) {
  const std::array<bool, 6> rov4{true, true, false, false, false, true};
  const std::array<bool, 6> rov6{true, true, true, false, true, true};
  ModePlan p;
  std::string why;
  EXPECT_TRUE(plan_rov_mode(M::HEADING_HOLD, rov4, false, false, "rov4", p, why)) << why;
  EXPECT_EQ(p.roles, (std::array<AxisRole, 6>{P, P, O, O, O, H}));
  EXPECT_FALSE(plan_rov_mode(M::DEPTH_HOLD, rov4, true, true, "rov4", p, why));
  EXPECT_EQ(why, "depth hold refused: rov4 cannot actuate heave (Z)");
  EXPECT_FALSE(plan_rov_mode(M::STABILISE, rov4, true, true, "rov4", p, why));
  EXPECT_EQ(why, "stabilise refused: rov4 cannot actuate roll (K) or pitch (M)");
  EXPECT_TRUE(plan_rov_mode(M::STABILISE, rov6, false, true, "rov6", p, why));
  EXPECT_EQ(p.roles, (std::array<AxisRole, 6>{P, P, P, O, H, R}));
  EXPECT_TRUE(p.level);
  EXPECT_TRUE(plan_rov_mode(M::RATE, rov6, false, true, "rov6", p, why));
  EXPECT_EQ(p.roles, (std::array<AxisRole, 6>{P, P, P, O, R, R}));
  EXPECT_FALSE(plan_rov_mode(M::POSITION_HOLD, rov6, false, true, "rov6", p, why));
  EXPECT_EQ(why, "position hold refused: the odometry carries no valid position");
  EXPECT_TRUE(plan_rov_mode(M::POSITION_HOLD, rov6, true, true, "rov6", p, why));
  EXPECT_EQ(p.roles, (std::array<AxisRole, 6>{H, H, H, O, H, H}));
  EXPECT_FALSE(plan_rov_mode(M::MANUAL_CLOSED_LOOP, rov6, true, true, "rov6", p, why));
  // Without a valid depth: what uses it is refused, what does not flies (heading hold on the
  // 4-thruster ROV above, stabilise and rate here).
  for (std::int8_t m : {M::DEPTH_HOLD, M::SURFACE, M::POSITION_HOLD}) {
    EXPECT_FALSE(plan_rov_mode(m, rov6, true, false, "rov6", p, why));
    EXPECT_EQ(why,
              std::string(rov_mode_words(m)) + " refused: the odometry carries no valid depth");
  }
  for (std::int8_t m : {M::STABILISE, M::HEADING_HOLD, M::RATE})
    EXPECT_TRUE(plan_rov_mode(m, rov6, false, false, "rov6", p, why)) << why;
  EXPECT_EQ(rov_mode_from_name("depth_hold"), M::DEPTH_HOLD);
  EXPECT_EQ(rov_mode_from_name("deep"), -1);
}

TEST(RovConfig, AMisspeltKeyIsRefusedNamingIt) {
  const std::string text = std::string("rov_control:\n  vehicle: ") + TILLER_SOURCE_DIR +
                           "/config/vehicles/seed001_rov6.yaml\n  axes:\n    heave: {kpp: 3}\n";
  const auto root = config::Value::parse(text, "rov.yaml");
  load_rov_control(root);
  try {
    root.check_all_used();
    FAIL() << "accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("rov_control.axes.heave.kpp"), std::string::npos)
        << e.what();
  }
  const auto bad = config::Value::parse("rov_control:\n  vehicle: nowhere.yaml\n", "rov.yaml");
  EXPECT_THROW(load_rov_control(bad), config::Error);
}

}  // namespace
}  // namespace tiller::control
