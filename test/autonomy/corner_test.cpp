// Issue 13 findings 2 and 4 on the Otter in lockstep (full plant: simulator, ESC, mixer) over
// config/missions/long_course.yaml (legs of 150-250 m, four 90 deg corners and a hairpin), at
// the shipped 1.5 m/s cruise: the shipped settings (world_integral, wheel-over from turn_rate
// 0.7 rad/s) against their measured scores; no setpoint above max_speed for any law in 0.3 m/s
// current; each law's steady cross-track (60 s after each switch) below its measured value with
// a margin; integral LOS with turn_rate 0.5 overshoots no corner by more than 0.3 m in still
// water (without turn anticipation: 0.95 m). Numbers: docs/tuning.md.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "harness.hpp"
#include "plants.hpp"

namespace tiller::test {
namespace {

RunResult fly(guidance::CrossTrackLaw law, double current, double toward_deg,
              double turn_rate = -1) {
  const auto& otter = plants()[0];
  RunConfig c;
  c.mission_file = "config/missions/long_course.yaml";
  c.guidance_file = otter.guidance_file;
  c.control_file = otter.control_file;
  c.make_plant = otter.make;
  c.pose_channel = otter.pose_channel;
  c.current_speed = current;
  c.current_from_deg = toward_deg + 180;
  c.tweak_follower = [=](guidance::FollowerNodeParams& p) {
    p.follower.law = law;
    if (turn_rate >= 0) p.follower.turn_rate = turn_rate;
  };
  return run_mission(c);
}

// The Otter's shipped guidance (config/guidance/otter.yaml: world_integral, turn_rate 0.7).
RunResult fly_shipped(double current, double toward_deg) {
  const auto& otter = plants()[0];
  RunConfig c;
  c.mission_file = "config/missions/long_course.yaml";
  c.guidance_file = otter.guidance_file;
  c.control_file = otter.control_file;
  c.make_plant = otter.make;
  c.pose_channel = otter.pose_channel;
  c.current_speed = current;
  c.current_from_deg = toward_deg + 180;
  return run_mission(c);
}

// Issue 13 findings 2 and 4 with the shipped settings, and the current estimate carried through
// corners (turn_drift_rate 0.45: the wheel-over point moved by the drift the estimate predicts in
// the turn; world_integral kept whole and applied across each leg; not integrated in the turn).
// Measured (with the Otter's station keeping of config/control/otter.yaml: ki 10, i_limit 30 N),
// the code before in brackets: still water overshoot 0.360 m (0.451), steady 0.011 (0.010),
// final 0.003 (0.005); toward 90 deg 0.466 (1.523), 0.030 (0.027), 0.086 (0.118); toward 180
// 0.506 (1.487), 0.017 (0.014), 0.018 (0.026); toward 270 0.518 (0.565), 0.025 (0.026), 0.073
// (0.010); max setpoint 1.500. Final error: issue 13's 0.10 m. The first corner is not in these
// directions' worst: the current along the first leg is unknown there (1.5 m outside toward 0 deg,
// docs/tuning.md).
TEST(Corners, ShippedOtterSettingsTurnEarlyAndStayAtOrBelowMaxSpeed) {
  struct Case {
    double current, toward_deg;
    double overshoot_below, steady_below, final_below;  // m: measured with a margin
  };
  const Case cases[] = {{0, 0, 0.4, 0.015, 0.02},
                        {0.3, 90, 0.55, 0.035, 0.10},
                        {0.3, 180, 0.6, 0.02, 0.10},
                        {0.3, 270, 0.6, 0.035, 0.10}};
  for (const auto& k : cases) {
    SCOPED_TRACE(std::to_string(k.current) + " m/s toward " + std::to_string(k.toward_deg));
    const auto r = fly_shipped(k.current, k.toward_deg);
    ASSERT_TRUE(r.completed);
    std::printf("current %.1f toward %.0f: overshoot %.3f steady %.4f final %.3f max_sp %.3f\n",
                k.current, k.toward_deg, r.corners.max_overshoot, r.corners.steady_cross_track_rms,
                r.path.final_position_error, r.max_setpoint_speed);
    EXPECT_EQ(r.corners.overshoot.size(), 5u);
    EXPECT_LT(r.corners.max_overshoot, k.overshoot_below);
    EXPECT_LT(r.corners.steady_cross_track_rms, k.steady_below);
    EXPECT_GE(r.held_s, 30.0);
    EXPECT_LT(r.path.final_position_error, k.final_below);
    EXPECT_LE(r.max_setpoint_speed, 1.5 + 1e-9);
    EXPECT_EQ(r.path.waypoints_missed, 0);  // the wheel-over arc passes 0.53 m inside
  }
}

TEST(Corners, IntegralLosWithWheelOverOvershootNoCornerByMoreThan30cm) {
  const auto r = fly(guidance::CrossTrackLaw::kIntegral, 0, 0, 0.5);
  ASSERT_TRUE(r.completed);
  EXPECT_EQ(r.corners.overshoot.size(), 5u);
  EXPECT_LT(r.corners.max_overshoot, 0.3);  // measured 0.257 m
  EXPECT_LT(r.corners.steady_cross_track_rms, 0.03);
  // Without turn anticipation the boat passes outside every corner (finding 4: 0.8-1 m).
  EXPECT_GT(fly(guidance::CrossTrackLaw::kIntegral, 0, 0, 0).corners.max_overshoot, 0.7);
}

TEST(Corners, EveryLawInCurrentStaysAtOrBelowMaxSpeedAndConverges) {
  struct Case {
    guidance::CrossTrackLaw law;
    double steady_below;  // m: measured value (toward 90 deg) with a margin
  };
  // los keeps a standing offset (about Delta tan(asin(c_n / U)) = 1 m): measured 0.92 m.
  const Case cases[] = {{guidance::CrossTrackLaw::kSeed, 0.6},
                        {guidance::CrossTrackLaw::kLos, 1.1},
                        {guidance::CrossTrackLaw::kIntegral, 0.2},
                        {guidance::CrossTrackLaw::kAdaptive, 0.25}};
  for (const auto& k : cases) {
    SCOPED_TRACE(static_cast<int>(k.law));
    // turn_rate as in the docs/tuning.md table: seed 0, the LOS laws 0.5 rad/s.
    const auto r = fly(k.law, 0.3, 90, k.law == guidance::CrossTrackLaw::kSeed ? 0 : 0.5);
    ASSERT_TRUE(r.completed);
    EXPECT_LE(r.max_setpoint_speed, 1.5 + 1e-9);
    EXPECT_GT(r.corners.steady_samples, 1000);
    EXPECT_LT(r.corners.steady_cross_track_rms, k.steady_below);
  }
}

}  // namespace
}  // namespace tiller::test
