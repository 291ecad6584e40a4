// Closed loop in lockstep: missions complete without missing a waypoint, end within 0.5 m of
// the goal (the wayfinding course within issue 13's 0.10 m), hold station for 120 s, hand over
// without a thrust step; the velocity PID's step response. In a 0.3 m/s current from 30 deg;
// station keeping after a straight approach in a current from 8 directions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/angles.hpp"
#include "harness.hpp"
#include "plants.hpp"
#include "simple_plant.hpp"
#include "step_response.hpp"

namespace tiller::test {
namespace {

struct Case {
  std::string name;
  std::string control;
  std::string guidance;
  std::function<std::vector<std::unique_ptr<Node>>(const mission::Mission&, double, double)> plant;
  std::string pose_channel;
};

// The full stack (mixer + esc + simulator) on the Otter and seed 004's X and H drive boats.
std::vector<Case> cases() {
  std::vector<Case> c;
  for (const auto& p : plants())
    c.push_back({p.name, p.control_file, p.guidance_file, p.make, p.pose_channel});
  return c;
}

TEST(ClosedLoop, WayfindingCourseCompletesWithoutMissingAWaypoint) {
  for (const auto& k : cases()) {
    RunConfig c;
    c.mission_file = "config/missions/vrx_wayfinding.yaml";
    c.control_file = k.control;
    c.guidance_file = k.guidance;
    c.make_plant = k.plant;
    c.pose_channel = k.pose_channel;
    const auto r = run_mission(c);
    SCOPED_TRACE(k.name);
    EXPECT_TRUE(r.completed);
    EXPECT_EQ(r.skipped, 0);                // the follower never passed a point outside 1 m
    EXPECT_EQ(r.path.waypoints_missed, 0);  // every point reached in order within 1 m
    // Issue 13 targets: final error <= 0.10 m; the cross-track RMS and corner overshoot at their
    // measured values with a margin. Measured (the old code: world_integral kept whole across a
    // corner, turn_rate 0, in brackets): Otter final 0.069 m (0.261), RMS 0.232 (0.345),
    // overshoot 1.189 (1.320); X 0.000, 0.086, 0.132 (0.104); H 0.000, 0.073, 0.121 (0.090).
    // The current estimate carried through corners (turn_drift_rate) and the Otter's station
    // keeping (ki 10, i_limit 30 N): final 0.083, RMS 0.193, overshoot 0.639 (before: 0.069,
    // 0.232, 1.189).
    const bool otter = k.name == "otter";
    EXPECT_LE(r.path.final_position_error, 0.10);
    EXPECT_LT(r.path.cross_track_rms, otter ? 0.21 : 0.1);
    EXPECT_LT(r.corners.max_overshoot, otter ? 0.7 : 0.2);
    EXPECT_LT(r.max_switch_jump, 20.0);  // N per 50 ms after a hand-over: no step
    std::printf("%s wayfinding: final %.3f xte_rms %.3f overshoot %.3f switch step %.2f N\n",
                k.name.c_str(), r.path.final_position_error, r.path.cross_track_rms,
                r.corners.max_overshoot, r.max_switch_jump);
  }
}

TEST(ClosedLoop, StationKeepingHolds120s) {
  for (const auto& k : cases()) {
    RunConfig c;
    c.mission_file = "config/missions/station_keeping.yaml";
    c.control_file = k.control;
    c.guidance_file = k.guidance;
    c.make_plant = k.plant;
    c.pose_channel = k.pose_channel;
    const auto r = run_mission(c);
    SCOPED_TRACE(k.name);
    ASSERT_TRUE(r.completed);
    EXPECT_GE(r.held_s, 120.0);
    // After 10 s to settle, never more than 1 m from the goal; ends within 0.5 m.
    EXPECT_LT(r.station_max_distance, 1.0);
    EXPECT_LT(r.path.final_position_error, 0.5);
  }
}

// Issue 13 finding 3: arriving with the current behind, the Otter overshot, turned round and
// settled 0.67 m to the side for good: its station integral lay partly along sway, which never
// integrated. A straight approach north (test/autonomy/arrive_mission.yaml) in a 0.3 m/s current
// toward each of 8 directions (0 deg: from behind), then 30 s of station keeping: the goal within
// 0.10 m at the end, on the Otter (weathervaning) and the X and H drives (holding the heading).
// Before the fix the Otter ended 1.30 m off (current toward 45 and 315 deg) and 0.31 m (90, 270).
TEST(ClosedLoop, StationKeepingEndsOnTheGoalWhateverTheCurrentsDirection) {
  for (const auto& k : cases()) {
    double worst = 0;
    for (int toward = 0; toward < 360; toward += 45) {
      RunConfig c;
      c.mission_file = "test/autonomy/arrive_mission.yaml";
      c.control_file = k.control;
      c.guidance_file = k.guidance;
      c.make_plant = k.plant;
      c.pose_channel = k.pose_channel;
      c.current_speed = 0.3;
      c.current_from_deg = toward + 180;
      const auto r = run_mission(c);
      SCOPED_TRACE(k.name + ", current toward " + std::to_string(toward) + " deg");
      ASSERT_TRUE(r.completed);
      EXPECT_GE(r.held_s, 30.0);
      EXPECT_LE(r.path.final_position_error, 0.10);
      worst = std::max(worst, r.path.final_position_error);
    }
    std::printf("%s: final error after 30 s, worst of 8 current directions: %.3f m\n",
                k.name.c_str(), worst);
  }
}

// Issue 13's final-error target after a course, not only a straight approach: the Otter 30 s
// after completing the box, the wayfinding course and the station-keeping task, in the
// directions where it ended farthest off. Before (station keeping ki 6, i_limit 60 N, the
// heading held below 8 N): box toward 315 deg 0.396 m (the integral wound up to 60 N in the
// arrival's turn, the boat overshot 2 m and came back slowly), toward 180 0.107; wayfinding
// toward 0 0.150, toward 180 0.149; station keeping in still water 0.182 (a sideways error under
// min_force / kp = 0.2 m was never corrected), toward 315 0.211.
TEST(ClosedLoop, OtterEndsWithin10cmAfterACourseWhateverTheCurrent) {
  struct Arrival {
    const char* mission;
    double current, toward_deg;
  };
  const Arrival cases[] = {{"config/missions/default.yaml", 0.3, 315},
                           {"config/missions/default.yaml", 0.3, 180},
                           {"config/missions/vrx_wayfinding.yaml", 0.3, 0},
                           {"config/missions/vrx_wayfinding.yaml", 0.3, 180},
                           {"config/missions/station_keeping.yaml", 0, 0},
                           {"config/missions/station_keeping.yaml", 0.3, 315}};
  const auto& otter = plants()[0];
  for (const auto& a : cases) {
    RunConfig c;
    c.mission_file = a.mission;
    c.control_file = otter.control_file;
    c.guidance_file = otter.guidance_file;
    c.make_plant = otter.make;
    c.pose_channel = otter.pose_channel;
    c.current_speed = a.current;
    c.current_from_deg = a.toward_deg + 180;
    c.hold_s = 30;
    const auto r = run_mission(c);
    SCOPED_TRACE(std::string(a.mission) + ", toward " + std::to_string(a.toward_deg));
    ASSERT_TRUE(r.completed);
    EXPECT_GE(r.held_s, 30.0);
    EXPECT_LE(r.path.final_position_error, 0.10);
    std::printf("%s, %.1f m/s toward %.0f deg: final %.3f m\n", a.mission, a.current, a.toward_deg,
                r.path.final_position_error);
  }
}

TEST(ClosedLoop, RepeatedPointsAndZeroLengthSegmentsStillComplete) {
  for (const auto& k : cases()) {
    RunConfig c;
    c.mission_file = "test/autonomy/bad_path_mission.yaml";
    c.control_file = k.control;
    c.guidance_file = k.guidance;
    c.make_plant = k.plant;
    c.pose_channel = k.pose_channel;
    const auto r = run_mission(c);
    SCOPED_TRACE(k.name);
    EXPECT_TRUE(r.completed);
    EXPECT_EQ(r.skipped, 0);
    EXPECT_LT(r.path.final_position_error, 0.5);
    for (const auto& p : r.poses) ASSERT_TRUE(std::isfinite(p.north) && std::isfinite(p.east));
  }
}

TEST(ClosedLoop, TranslationHoldsTheHeadingWhileMoving) {
  for (std::size_t v : {1u, 2u}) {  // seed 004 X and H drive
    RunConfig c;
    c.mission_file = "test/autonomy/translation_mission.yaml";
    c.control_file = plants()[v].control_file;
    c.guidance_file = plants()[v].guidance_file;
    c.make_plant = plants()[v].make;
    c.pose_channel = plants()[v].pose_channel;
    const auto r = run_mission(c);
    SCOPED_TRACE(plants()[v].name);
    EXPECT_TRUE(r.completed);
    EXPECT_EQ(r.path.waypoints_missed, 0);
    EXPECT_LT(r.path.final_position_error, 0.5);
    double worst = 0;
    for (const auto& p : r.poses) worst = std::max(worst, std::abs(angle_diff(p.heading, kPi / 2)));
    EXPECT_LT(worst, 0.15);  // rad: never turned toward the direction of travel
  }
}

TEST(ClosedLoop, DefaultMissionIsShort) {
  RunConfig c;  // config/missions/default.yaml, on the Otter
  c.make_plant = plants()[0].make;
  c.guidance_file = plants()[0].guidance_file;
  c.pose_channel = plants()[0].pose_channel;
  const auto r = run_mission(c);
  EXPECT_TRUE(r.completed);
  EXPECT_LT(r.completed_at + r.mission.station_keep_s, 120.0);  // well under 3 minutes
  EXPECT_EQ(r.path.waypoints_missed, 0);
  EXPECT_LT(r.path.final_position_error, 0.5);
}

// The default mission is a closed box: it starts where it ends, at a goal with a 180 deg
// heading. The goal heading applies only on the last leg, so the Otter leaves the start along
// the first leg (before the fix it was told to face south there: yaw -0.72 rad, 2.2 m east in
// the first 8 s, a max cross-track of 2.24 m).
TEST(ClosedLoop, ClosedCourseLeavesTheStartAlongTheFirstLeg) {
  RunConfig c;  // config/missions/default.yaml
  c.make_plant = plants()[0].make;
  c.guidance_file = plants()[0].guidance_file;
  c.pose_channel = plants()[0].pose_channel;
  const auto r = run_mission(c);
  ASSERT_TRUE(r.completed);
  double worst_yaw = 0, worst_east = 0, first_leg = 0;
  bool on_first_leg = true;
  for (const auto& p : r.poses) {
    if (p.north > 19.0) on_first_leg = false;  // the first corner is at (20, 0)
    if (on_first_leg) first_leg = std::max(first_leg, std::abs(p.east));
    if (p.t > 8.0) continue;
    worst_yaw = std::max(worst_yaw, std::abs(angle_diff(p.heading, 0.0)));
    worst_east = std::max(worst_east, std::abs(p.east));
  }
  EXPECT_LT(worst_yaw, 0.3);   // rad (was 0.72)
  EXPECT_LT(worst_east, 0.6);  // m (was 2.2)
  // The whole first leg within 0.6 m of its line (the old 2.24 m max was there); the course's
  // max is now at a corner, where the current sets the boat out of the turn.
  EXPECT_LT(first_leg, 0.6);
  EXPECT_LT(r.path.cross_track_max, 2.24);
  std::printf(
      "otter default: first 8 s |yaw| <= %.2f rad, |east| <= %.2f m; first leg %.2f m; xte max "
      "%.2f m\n",
      worst_yaw, worst_east, first_leg, r.path.cross_track_max);
}

TEST(ClosedLoop, SameRunSameResult) {
  RunConfig c;
  c.make_plant = plants()[1].make;
  c.guidance_file = plants()[1].guidance_file;
  c.pose_channel = plants()[1].pose_channel;
  const auto a = run_mission(c), b = run_mission(c);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t k = 0; k < a.poses.size(); ++k) {
    ASSERT_EQ(a.poses[k].north, b.poses[k].north);
    ASSERT_EQ(a.poses[k].east, b.poses[k].east);
  }
}

// The autonomy alone against the stand-in Otter model (test/autonomy/simple_plant.hpp), which
// is what the loop was developed on before the simulator landed.
TEST(ClosedLoop, StandInPlantCompletesTheDefaultMission) {
  RunConfig c;
  const auto r = run_mission(c);
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.path.waypoints_missed, 0);
  EXPECT_LT(r.path.final_position_error, 0.5);
}

// Surge step 0 -> 1.5 m/s in still water. Each hull's surge is first order, m du/dt = -D(u) u + X,
// and the PID's drag feed-forward cancels D(u) at the setpoint, so the error decays with
// tau = m / (D + k_error): Otter 85.5 / (77.55 + 150) = 0.38 s; seed 004's boat
// 180 / (51.3 + 72.4 * 1.5 + 300) = 0.39 s; both behind a 0.1 s thruster lag and an initial
// stretch at full thrust (Otter 240 N for ~0.5 s). 5 % settling ~ 3 tau + lag + saturation,
// about 1.5-2 s: we require 2 s, and an overshoot under 10 %.
TEST(ClosedLoop, VelocityPidStepResponse) {
  auto all = cases();
  const auto& s = standin_plant();
  all.push_back({s.name, s.control_file, s.guidance_file, s.make, s.pose_channel});
  for (const auto& k : all) {
    SCOPED_TRACE(k.name);
    mission::Mission m;
    const auto r = velocity_step(k.control, 1.5, k.plant(m, 0.0, 0.0));
    EXPECT_LT(r.overshoot, 0.10);
    EXPECT_GT(r.settle_s, 0.0);
    EXPECT_LT(r.settle_s, 2.0);
    EXPECT_NEAR(r.final_speed, 1.5, 0.02);  // the integrator removes any drag mismatch
    std::printf(
        "%s: step 0 -> 1.5 m/s: overshoot %.1f %%, rise (90 %%) %.2f s, settle (5 %%) %.2f s\n",
        k.name.c_str(), 100 * r.overshoot, r.rise_s, r.settle_s);
  }
}

// Sway (seed 004's X and H drives; the Otter has no sway authority) and yaw-rate steps, in
// still water, the other axes held at zero. Same first-order argument as for surge: the drag
// feed-forward cancels the hull's damping at the setpoint, so the error decays with
// tau = m / (D + k_error):
//   sway, X/H: 180 / (40 + 300) = 0.53 s; yaw rate, X/H: 446 / (400 + 600) = 0.45 s;
//   yaw rate, Otter: 42.65 / (42.65 + 60) = 0.42 s (its quadratic yaw damping, 426.5 |r| r, is
//   fed forward too: without it the PID reached 0.24 of 0.3 rad/s). The Otter's step is
//   0.2 rad/s: its two propellers give at most 0.395 * (119.7 + 66.7) = 74 N m, so it turns
//   at 0.29 rad/s at most. The X and H drives' yaw and sway ki were lowered (200 -> 80, 40 -> 10):
//   an integrator that winds up during the rise and unwinds at ki / (D + k_error) = 0.2 /s left
//   a 4 s tail outside the 5 % band (overshoot 7.7 %, settling 4.3 s; sway 5 %, 2.7 s).
// Behind the 0.1 s thruster lag, 5 % settling is 3 tau + lag, 1.4-1.7 s: we require 2 s and an
// overshoot under 10 %, as for surge.
TEST(ClosedLoop, VelocityPidSwayAndYawRateSteps) {
  struct Step {
    std::string vehicle;
    StepAxis axis;
    double command;
    const char* what;
  };
  std::vector<Step> steps = {{"seed004_usv_x", StepAxis::kSway, 0.5, "sway 0 -> 0.5 m/s"},
                             {"seed004_usv_h", StepAxis::kSway, 0.5, "sway 0 -> 0.5 m/s"},
                             {"otter", StepAxis::kYawRate, 0.2, "yaw rate 0 -> 0.2 rad/s"},
                             {"seed004_usv_x", StepAxis::kYawRate, 0.3, "yaw rate 0 -> 0.3 rad/s"},
                             {"seed004_usv_h", StepAxis::kYawRate, 0.3, "yaw rate 0 -> 0.3 rad/s"}};
  for (const auto& st : steps) {
    const PlantSpec* k = nullptr;
    for (const auto& p : plants()) {
      if (p.name == st.vehicle) k = &p;
    }
    ASSERT_NE(k, nullptr);
    SCOPED_TRACE(st.vehicle + ": " + st.what);
    mission::Mission m;
    const auto r = velocity_step(k->control_file, st.command, k->make(m, 0.0, 0.0), 15, st.axis);
    EXPECT_LT(r.overshoot, 0.10);
    EXPECT_GT(r.settle_s, 0.0);
    EXPECT_LT(r.settle_s, 2.0);
    EXPECT_NEAR(r.final_speed, st.command, 0.02 * st.command);
    std::printf(
        "%s: %s: overshoot %.1f %%, rise (90 %%) %.2f s, settle (5 %%) %.2f s, final %.3f\n",
        st.vehicle.c_str(), st.what, 100 * r.overshoot, r.rise_s, r.settle_s, r.final_speed);
  }
}

}  // namespace
}  // namespace tiller::test
