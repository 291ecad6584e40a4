// tiller-tune's identification and proposal on hand-made records: a one-axis model integrated
// finely (RK4 at 1 ms, the thrust lag in closed form) and sampled at 20 Hz as the simulator's
// ground truth is, recovered within 1 %; the window selection (a turn is not surge drag); the
// config text edits and their diff.
#include <gtest/gtest.h>

#include <cmath>

#include "tune/identify.hpp"
#include "tune/text_edit.hpp"

namespace tiller::tune {
namespace {

struct Axis1 {
  double m, d, d2, tc;
  double g = 0;  // constant force (heave: weight less buoyancy), N
};

// Steps of the target wrench on `axis` (N): (start s, value); sampled every 50 ms.
Record simulate(const Axis1& p, int axis, const std::vector<std::pair<double, double>>& steps,
                double end_s) {
  Record r;
  for (const auto& [t, v] : steps) {
    WrenchTarget w;
    w.t = t;
    w.tau[kWrenchIndex[axis]] = v;
    r.targets.push_back(w);
  }
  double nu = 0, f = 0, c = 0;
  std::size_t j = 0;
  const double h = 0.001;
  int k = 0;
  for (double t = 0; t <= end_s + 1e-9; t = ++k * h) {
    if (k % 50 == 0) {
      MotionSample s;
      s.t = t;
      s.nu[static_cast<std::size_t>(kNuIndex[axis])] = nu;
      r.motion.push_back(s);
    }
    while (j < steps.size() && steps[j].first <= t + 1e-12) c = steps[j++].second;
    // RK4 on nu with f(t) = c + (f0 - c) exp(-(t - t0) / tc) over the step.
    const auto force = [&](double dt) { return c + (f - c) * std::exp(-dt / p.tc); };
    const auto acc = [&](double v, double fo) {
      return (fo + p.g - p.d * v - p.d2 * std::fabs(v) * v) / p.m;
    };
    const double k1 = acc(nu, force(0));
    const double k2 = acc(nu + 0.5 * h * k1, force(0.5 * h));
    const double k3 = acc(nu + 0.5 * h * k2, force(0.5 * h));
    const double k4 = acc(nu + h * k3, force(h));
    nu += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    f = force(h);
  }
  return r;
}

const std::vector<std::pair<double, double>> kSurgeSteps = {
    {1, 80}, {12, 160}, {22, 240}, {32, 0}, {44, 120}, {52, 0}, {64, -90}, {72, 0}};

TEST(Identify, RecoversASurgeModelWithin1Percent) {
  const Axis1 p{85.5, 77.55, 12.0, 0.1};
  const Identified id = identify(simulate(p, kSurge, kSurgeSteps, 86));
  const auto& a = id.axis[kSurge];
  ASSERT_TRUE(a.identified) << a.why;
  EXPECT_NEAR(a.mass.value, p.m, 0.01 * p.m);
  EXPECT_NEAR(a.linear.value, p.d, 0.01 * p.d);
  EXPECT_NEAR(a.quadratic.value, p.d2, 0.01 * p.d2);
  EXPECT_NEAR(id.time_constant, p.tc, 0.01 * p.tc);
  EXPECT_LT(id.time_constant_low, p.tc * 1.01);
  EXPECT_GT(id.time_constant_high, p.tc * 0.99);
  // The standard deviations are small and positive on a noise-free record.
  EXPECT_GT(a.mass.std, 0);
  EXPECT_LT(a.mass.std, 0.01 * p.m);
  EXPECT_FALSE(id.axis[kYaw].identified);
  EXPECT_NE(id.axis[kYaw].why.find("not driven"), std::string::npos);
}

TEST(Identify, RecoversAYawModelWithQuadraticDamping) {
  const Axis1 p{41.7, 42.65, 476.5, 0.25};
  const Identified id =
      identify(simulate(p, kYaw, {{1, 20}, {11, 0}, {19, -52}, {29, 0}, {37, 35}, {45, 0}}, 55));
  const auto& a = id.axis[kYaw];
  ASSERT_TRUE(a.identified) << a.why;
  EXPECT_NEAR(a.mass.value, p.m, 0.01 * p.m);
  EXPECT_NEAR(a.linear.value, p.d, 0.01 * p.d);
  EXPECT_NEAR(a.quadratic.value, p.d2, 0.01 * p.d2);
  EXPECT_NEAR(id.time_constant, p.tc, 0.01 * p.tc);
}

TEST(Identify, RecoversHeaveWithTheWeightLessBuoyancy) {
  // A BlueROV2-like heave: 2.08 N buoyant (g = -2.08 N, + down), thrust steps both ways.
  const Axis1 p{21.0, 8.0, 60.0, 0.1, -2.08};
  const Identified id =
      identify(simulate(p, kHeave, {{1, 30}, {9, 0}, {17, -25}, {25, 0}, {33, 15}, {41, 0}}, 50));
  const auto& a = id.axis[kHeave];
  ASSERT_TRUE(a.identified) << a.why;
  EXPECT_NEAR(a.mass.value, p.m, 0.01 * p.m);
  EXPECT_NEAR(a.linear.value, p.d, 0.01 * p.d);
  EXPECT_NEAR(a.quadratic.value, p.d2, 0.01 * p.d2);
  EXPECT_NEAR(a.bias.value, p.g, 0.02);
}

TEST(Identify, AWindowWithAnotherAxisMovingIsNotUsed) {
  const Axis1 p{85.5, 77.55, 0, 0.1};
  Record r = simulate(p, kSurge, kSurgeSteps, 86);
  const int all = identify(r).axis[kSurge].windows;
  // A yaw rate through the first 20 s: those windows are not pure surge.
  for (auto& s : r.motion)
    if (s.t < 20) s.nu[5] = 0.2;
  const Identified id = identify(r);
  EXPECT_LE(id.axis[kSurge].windows, all - 19);
  EXPECT_NEAR(id.axis[kSurge].linear.value, p.d, 0.01 * p.d);
}

TEST(Identify, TooFewWindowsIsNotIdentifiedWithTheReason) {
  const Axis1 p{85.5, 77.55, 0, 0.1};
  const Identified id = identify(simulate(p, kSurge, {{0.5, 100}}, 4));
  EXPECT_FALSE(id.axis[kSurge].identified);
  EXPECT_NE(id.axis[kSurge].why.find("windows"), std::string::npos) << id.axis[kSurge].why;
}

TEST(TextEdit, SetsAFlowMapKeyAndABlockScalarKeepingComments) {
  auto lines = split_lines(
      "velocity_pid:\n"
      "  surge: {k_drag: 77.5, k_drag_quad: 0, k_error: 150}  # gains\n"
      "  yaw:   {k_drag: 42.65, k_drag_quad: 426.5}\n"
      "follower:\n"
      "  turn_rate: 0.7              # rad/s\n"
      "  turn_drift_rate: 0.45\n");
  const auto before = lines;
  set_value(lines, {"velocity_pid", "surge"}, "80.1", "k_drag");
  set_value(lines, {"velocity_pid", "yaw"}, "500", "k_drag_quad");
  set_value(lines, {"follower", "turn_rate"}, "0.56");
  EXPECT_EQ(lines[1], "  surge: {k_drag: 80.1, k_drag_quad: 0, k_error: 150}  # gains");
  EXPECT_EQ(lines[2], "  yaw:   {k_drag: 42.65, k_drag_quad: 500}");
  EXPECT_EQ(lines[4], "  turn_rate: 0.56             # rad/s");
  EXPECT_THROW(set_value(lines, {"follower", "nope"}, "1"), std::runtime_error);
  EXPECT_THROW(set_value(lines, {"velocity_pid", "surge"}, "1", "ki"), std::runtime_error);
  const std::string d = unified_diff("config/x.yaml", before, lines);
  EXPECT_EQ(d,
            "--- a/config/x.yaml\n+++ b/config/x.yaml\n@@ -1,6 +1,6 @@\n velocity_pid:\n"
            "-  surge: {k_drag: 77.5, k_drag_quad: 0, k_error: 150}  # gains\n"
            "+  surge: {k_drag: 80.1, k_drag_quad: 0, k_error: 150}  # gains\n"
            "-  yaw:   {k_drag: 42.65, k_drag_quad: 426.5}\n"
            "+  yaw:   {k_drag: 42.65, k_drag_quad: 500}\n"
            " follower:\n"
            "-  turn_rate: 0.7              # rad/s\n"
            "+  turn_rate: 0.56             # rad/s\n"
            "   turn_drift_rate: 0.45\n");
}

TEST(TextEdit, NumbersKeepFourSignificantDigits) {
  EXPECT_EQ(format_number(77.5512), "77.55");
  EXPECT_EQ(format_number(0.10004), "0.1");
  EXPECT_EQ(format_number(1234.56), "1235");
  EXPECT_EQ(format_number(-0.0123456), "-0.01235");
  EXPECT_EQ(format_number(0), "0");
}

}  // namespace
}  // namespace tiller::tune
