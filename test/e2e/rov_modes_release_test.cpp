// The ROV pilot modes in closed loop, continued (rov_rig.hpp; noise-free odometry, as the switch
// test: the numbers are the controller's, not the sensor's jitter): releasing a held axis' stick
// holds the new value smoothly (issue 15: "no thrust step", "releasing the stick holds the new
// value").
//   * depth hold, the hat pressed full down and released: no thruster's thrust changes by more
//     than kStepN per 10 ms (the mixer's 20 ms tick) on the press or the release; the depth
//     held is where the ROV stopped, and it stays within 1 cm of it (no overshoot back).
//     Before the rate setpoint was ramped (heave max_accel), the release stepped the setpoint
//     from 0.4 m/s to 0 and one vertical thruster by 56.9 N in one tick (rov_modes_live_test).
//   * heading hold released mid-turn, and heading hold engaged while the ROV still turns (a
//     coasting turn in manual): the heading settles on the value held, where the ROV stopped,
//     passing it by at most kOvershootDeg and swinging by at most kSwingDeg once held.
// Each prints its numbers (docs/flying.md, "ROV modes", has the table).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "rov_rig.hpp"

namespace tiller {
namespace {

using e2e::RovRig;
using e2e::RovSetup;
using M = controller_mode_t;

constexpr double kStepN = 2.5;         // N per 10 ms (7 % of 36 N), rov_modes_live_test's limit
constexpr double kOvershootDeg = 0.5;  // past the held heading
constexpr double kSwingDeg = 0.75;     // peak to peak once held (in the 0.3 m/s current)

RovSetup quiet(const std::string& v) {
  RovSetup s = e2e::rov_setup(v);
  if (v == "seed000_rov4") s.extra_buoyancy_n = 0;
  s.position_std_m = s.orientation_std_deg = s.velocity_std_m_s = s.rate_std_deg_s = 0;
  return s;
}

TEST(RovModes, HatPressAndReleaseInDepthHoldAreSmooth) {
  for (const char* v : {"bluerov2", "seed001_rov6"}) {
    RovRig r(quiet(v));
    r.command(M::DEPTH_HOLD);
    r.run(5'000);
    ASSERT_TRUE(r.rov.axes().holding(2)) << v;
    r.f.js.axes[5] = 32767;  // hat full down: descend at max_rate
    double fastest = 0;
    const double press =
        e2e::thrust_step(r, 3'000, [&] { fastest = std::max(fastest, r.nu()[2]); });
    const double at_release = r.depth();
    r.f.js.axes[5] = 0;
    double deepest = 0, t_held = -1, t = 0;
    const double release = e2e::thrust_step(r, 3'000, [&] {
      t += 0.01;
      deepest = std::max(deepest, r.depth());
      if (t_held < 0 && r.rov.axes().holding(2)) t_held = t;
    });
    ASSERT_TRUE(r.rov.axes().holding(2)) << v;
    const double target = r.rov.axes().target(2);
    double off = 0;
    r.run(5'000, [&] { off = std::max(off, std::fabs(r.depth() - target)); });
    std::printf(
        "%s depth hold, hat full down 3 s (%.2f m/s) then released: largest thrust change %.2f N "
        "(press) / %.2f N (release) per 10 ms; held after %.2f s at %.3f m (released at %.3f m, "
        "deepest %.3f m), then within %.4f m for 5 s\n",
        v, fastest, press, release, t_held, target, at_release, deepest, off);
    EXPECT_LE(press, kStepN) << v;
    EXPECT_LE(release, kStepN) << v;
    EXPECT_LE(deepest - target, 0.01) << v;  // held where it stopped
    EXPECT_LE(off, 0.01) << v;
  }
}

// How the heading settles on the held value after a release or an engagement.
struct Settle {
  double overshoot = 0;  // deg, past the held heading in the direction of the turn
  double swing = 0;      // deg, peak-to-peak over the 3 s after holding
  double held_after = -1;
  double stop_deg = 0;  // deg turned from the release (or engagement) to the held heading
};

Settle settle(RovRig& r, double turn_sign) {
  Settle out;
  const double yaw0 = r.eta()[5];
  std::vector<double> e;
  std::vector<double> yaw;
  double t = 0;
  r.run(4'000, [&] {
    t += 0.01;
    yaw.push_back(r.eta()[5]);
    if (out.held_after < 0 && r.rov.axes().holding(5)) out.held_after = t;
  });
  const double target = r.rov.axes().target(5);
  std::vector<double> after;
  for (std::size_t k = 0; k < yaw.size(); ++k) {
    const double d = turn_sign * rad_to_deg(angle_diff(yaw[k], target));  // + past it
    out.overshoot = std::max(out.overshoot, d);
    if (0.01 * static_cast<double>(k + 1) > out.held_after) after.push_back(d);
  }
  out.swing = e2e::p2p(after);
  out.stop_deg = turn_sign * rad_to_deg(angle_diff(target, yaw0));
  return out;
}

TEST(RovModes, HeadingHoldReleasedMidTurnSettlesWithoutOvershoot) {
  for (const char* v : {"bluerov2", "seed001_rov6"}) {
    RovRig r(quiet(v));
    r.command(M::HEADING_HOLD);
    r.run(3'000);
    ASSERT_EQ(r.rov.mode(), M::HEADING_HOLD) << r.rov.reason();
    r.f.js.axes[2] = 14000;  // twist clockwise, as rov_modes_live_test
    r.run(3'000);
    const double rate = r.nu()[5];
    r.f.js.axes[2] = 0;
    const Settle s = settle(r, 1.0);
    std::printf(
        "%s heading hold, twist released at %.2f rad/s: held after %.2f s, %.1f deg on; "
        "overshoot %.2f deg, swing %.2f deg\n",
        v, rate, s.held_after, s.stop_deg, s.overshoot, s.swing);
    EXPECT_GT(rate, 0.1) << v;
    EXPECT_LE(s.overshoot, kOvershootDeg) << v;
    EXPECT_LE(s.swing, kSwingDeg) << v;
  }
}

TEST(RovModes, HeadingHoldEngagedWhileTurning) {
  for (const char* v : {"bluerov2", "seed001_rov6"}) {
    RovRig r(quiet(v));
    r.f.js.axes[2] = 20000;  // manual: spin up clockwise
    r.run(2'000);
    r.f.js.axes[2] = 0;  // coast
    r.run(200);
    const double rate = r.nu()[5];
    r.command(M::HEADING_HOLD);
    const Settle s = settle(r, 1.0);
    std::printf(
        "%s heading hold engaged coasting at %.2f rad/s: held after %.2f s, %.1f deg on; "
        "overshoot %.2f deg, swing %.2f deg\n",
        v, rate, s.held_after, s.stop_deg, s.overshoot, s.swing);
    EXPECT_GT(rate, 0.1) << v;
    EXPECT_LE(s.overshoot, kOvershootDeg) << v;
    EXPECT_LE(s.swing, kSwingDeg) << v;
  }
}

}  // namespace
}  // namespace tiller
