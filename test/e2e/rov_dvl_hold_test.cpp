// Position hold on the DVL in closed loop (rov_dvl_scenarios.hpp; issue 34's targets), on the
// BlueROV2-class ROV: the hold in a 0.2 m/s current within 5 cm RMS of the held point, the
// recovery from a 20 N lateral step to within 10 % of its largest excursion in under 3 s, and a
// 10 s DVL dropout that falls back to depth and heading hold, holds both, does not resume by
// itself, and steps no thruster more than twice the steady hold's own largest change at the
// fallback or at the DVL's return. bench/rov_hold_figures prints the same figures.
#include <gtest/gtest.h>

#include <cstdio>

#include "rov_dvl_scenarios.hpp"

namespace tiller {
namespace {

using namespace e2e;
using M = controller_mode_t;

TEST(RovDvlHold, HoldsWithin5cmRmsInA02Current) {
  const HoldFigures h = hold_in_current("bluerov2", 0.2);
  std::printf(
      "hold: %.4f m RMS (largest %.4f), depth %.4f m RMS, heading %.3f deg RMS, estimate "
      "off by %.4f m\n",
      h.rms_m, h.max_m, h.depth_rms_m, h.heading_rms_deg, h.estimate_error_m);
  EXPECT_EQ(h.mode, M::POSITION_HOLD);
  EXPECT_LE(h.rms_m, 0.05);
  EXPECT_LE(h.depth_rms_m, 0.02);
  EXPECT_LE(h.heading_rms_deg, 1.0);
  EXPECT_LE(h.estimate_error_m, 0.05);
}

TEST(RovDvlHold, RecoversFromA20NLateralStepInUnder3s) {
  const StepFigures s = step_recovery("bluerov2", 20.0, 0.2);
  std::printf(
      "step: largest %.4f m at %.2f s, within 10 %% from %.2f s, final %.4f m (truly "
      "%.4f, %.4f)\n",
      s.peak_m, s.peak_at_s, s.within_10_s, s.final_m, s.truth_peak_m, s.truth_final_m);
  EXPECT_EQ(s.mode, M::POSITION_HOLD);
  EXPECT_GT(s.peak_m, 10 * s.jitter_m);  // the step did push it, well above the hold's jitter
  EXPECT_NEAR(s.truth_peak_m, s.peak_m, 0.01);
  ASSERT_GE(s.within_10_s, 0.0) << "never back within 10 %";
  EXPECT_LT(s.within_10_s, 3.0);
}

TEST(RovDvlHold, DropoutFallsBackAndDoesNotResumeOrStepTheThrust) {
  const DropoutFigures d = dvl_dropout("bluerov2", 0.2, 30.0, 10.0);
  std::printf(
      "dropout: fell back after %.2f s, drift %.3f m, depth %.4f m, heading %.3f deg; "
      "steps steady %.3f N, fallback %.3f N, return %.3f N\n",
      d.fallback_after_s, d.drift_m, d.depth_max_err_m, d.heading_max_err_deg, d.steady_step_n,
      d.fallback_step_n, d.recovery_step_n);
  EXPECT_EQ(d.mode_during, M::DEPTH_HEADING_HOLD) << d.reason;
  EXPECT_GT(d.fallback_after_s, 0.5);  // dvl.timeout_s 0.6 after the last report
  EXPECT_LT(d.fallback_after_s, 0.8);
  EXPECT_NE(d.reason.find("select position hold again"), std::string::npos) << d.reason;
  EXPECT_LE(d.depth_max_err_m, 0.05);
  EXPECT_LE(d.heading_max_err_deg, 2.0);
  EXPECT_EQ(d.mode_after, M::DEPTH_HEADING_HOLD);  // not resumed silently
  EXPECT_TRUE(d.estimate_valid_after);
  EXPECT_EQ(d.lost, 1);
  // No thrust step: no thruster changes by more in 10 ms at the fallback or at the DVL's return
  // than twice what it does in the steady hold (the sensors' noise through the gains).
  EXPECT_LE(d.fallback_step_n, 2 * d.steady_step_n);
  EXPECT_LE(d.recovery_step_n, 2 * d.steady_step_n);
}

}  // namespace
}  // namespace tiller
