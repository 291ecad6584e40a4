// StickScriptNode (tiller-stick-script's logic): a `held` measurement against the value at its
// first sample (hand-computed RMS and largest error, the limits), and odometry without a valid
// depth and attitude (odometry_t.valid) not taken: counted, and the step needing it fails.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/angles.hpp"
#include "runtime/channels.hpp"
#include "teleop/stick_script.hpp"

namespace tiller {
namespace {

constexpr TimeUs ms(double v) {
  return static_cast<TimeUs>(v * 1000);
}

StickScriptParams script(const std::string& steps) {
  return load_stick_script(config::Value::parse("rate_hz: 50\nsteps:\n" + steps));
}

struct Pilot {
  explicit Pilot(StickScriptParams p) : node(std::move(p)) {}
  void odom(double depth, double heading, TimeUs t, int valid = odometry_t::VALID_ALL) {
    odometry_t o{};
    o.utime = t;
    o.valid = valid;
    o.position[2] = depth;
    o.orientation[2] = heading;
    std::vector<std::uint8_t> b(static_cast<std::size_t>(o.getEncodedSize()));
    o.encode(b.data(), 0, static_cast<int>(b.size()));
    node.deliver(channels::kOdometry, b.data(), static_cast<int>(b.size()), t);
  }
  StickScriptNode node;
};

TEST(StickScript, HeldMeasuresAgainstTheFirstSample) {
  Pilot p(
      script("  - name: hold\n"
             "    hold_s: 0.05\n"
             "    measure: {depth: held, heading: held, max_depth_m: 0.15, max_heading_deg: 2}\n"));
  p.odom(1.0, 0.5, ms(0));
  p.node.tick(ms(0));  // odometry seen: the step starts
  ASSERT_EQ(p.node.step(), 0);
  // Samples at 20, 40, 60 ms: depth 1.0, 1.1, 0.9 against 1.0; heading 0.5, 0.5 + 1 deg,
  // 0.5 - 1 deg against 0.5. RMS sqrt((0 + 0.01 + 0.01) / 3) = 0.08165 m, largest 0.1 m;
  // heading RMS sqrt(2 / 3) deg = 0.8165 deg, largest 1 deg.
  const double d[] = {1.0, 1.1, 0.9};
  const double h[] = {0.5, 0.5 + deg_to_rad(1.0), 0.5 - deg_to_rad(1.0)};
  for (int i = 0; i < 3; ++i) {
    p.odom(d[i], h[i], ms(20 * (i + 1)));
    p.node.tick(ms(20 * (i + 1)));
  }
  ASSERT_TRUE(p.node.done());
  ASSERT_EQ(p.node.measures().size(), 1u);
  const StickMeasure& m = p.node.measures()[0];
  EXPECT_EQ(m.samples, 3);
  EXPECT_DOUBLE_EQ(m.depth_ref, 1.0);
  EXPECT_DOUBLE_EQ(m.heading_ref, 0.5);
  EXPECT_NEAR(m.depth_rms, std::sqrt(0.02 / 3), 1e-12);
  EXPECT_NEAR(m.depth_max, 0.1, 1e-12);
  EXPECT_NEAR(rad_to_deg(m.heading_rms), std::sqrt(2.0 / 3), 1e-9);
  EXPECT_NEAR(rad_to_deg(m.heading_max), 1.0, 1e-9);
  EXPECT_TRUE(m.passed);
  EXPECT_FALSE(p.node.failed());
}

TEST(StickScript, LargestErrorOverItsLimitFails) {
  Pilot p(script("  - {name: hold, hold_s: 0.03, measure: {depth: held, max_depth_m: 0.05}}\n"));
  p.odom(2.0, 0, ms(0));
  p.node.tick(ms(0));
  p.odom(2.06, 0, ms(20));  // 6 cm from the held 2.0 m: RMS 4.2 cm, largest 6 cm
  p.node.tick(ms(20));
  p.odom(2.0, 0, ms(40));
  p.node.tick(ms(40));
  ASSERT_TRUE(p.node.done());
  EXPECT_FALSE(p.node.measures()[0].passed);
  EXPECT_TRUE(p.node.failed());
  EXPECT_NE(p.node.report().find("OVER"), std::string::npos) << p.node.report();
}

TEST(StickScript, OdometryWithoutDepthOrAttitudeIsNotTaken) {
  Pilot p(script(
      "  - {name: dive, axes: {5: 32767}, until: {depth_at_least_m: 1.0}, timeout_s: 10}\n"));
  p.odom(0.0, 0, ms(0));
  p.node.tick(ms(0));
  ASSERT_EQ(p.node.step(), 0);
  ASSERT_EQ(p.node.stick().axes[5], 32767);
  // Deep enough, but the depth (then the attitude) is not valid: not taken, so not done.
  for (int i = 1; i <= 30; ++i) {
    const int valid = i % 2 ? int{odometry_t::VALID_ATTITUDE} : int{odometry_t::VALID_DEPTH};
    p.odom(1.5, 0, ms(20 * i), valid);
    p.node.tick(ms(20 * i));
  }
  EXPECT_EQ(p.node.counter_value("odometry.invalid"), 30);
  // 600 ms without a usable message (timeout 0.5 s): odometry lost, the step fails.
  EXPECT_TRUE(p.node.failed());
  EXPECT_NE(p.node.why().find("odometry lost"), std::string::npos) << p.node.why();
  EXPECT_EQ(p.node.stick().axes[5], 0);  // centred
}

}  // namespace
}  // namespace tiller
