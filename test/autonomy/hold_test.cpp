// Cancel, abort, pause hold position; resume continues; release disarms (issue 12, finding 9), in
// lockstep on the full Otter stack (simulator + ESC + mixer + path follower + velocity PID +
// station keeping + tiller-mission's node, which arms, starts and repeats its path every second)
// in a 0.3 m/s current from 30 deg, on a 150 m leg north flown at 1.5 m/s.
//   * A cancel (a path of 0 waypoints) at speed: the boat holds where it was (station keeping,
//     the arbiter's hold), within the stopping distance of the cancel point, for 60 s; the
//     mixer's gate stays ACTIVE and the thrust has no step (the hand-over blend). Before: the
//     thrust went to neutral, the boat coasted and drifted away with the current (and the
//     mission's next repeat restarted the path).
//   * ABORT: the same; the mission's repeats of the aborted path are ignored.
//   * PAUSE, then RESUME 20 s later: holds, then completes the leg.
//   * RELEASE: the mixer requests a disarm: disarmed, neutral.
//   * A vehicle that cannot hold (arbiter.hold_position false): a cancel gives neutral, then the
//     mixer's disarm after safety.disarm_after_s (3 s).
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/angles.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "plants.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {
namespace {

enum class Act { kCancel, kPause, kResume, kAbort, kRelease };

struct Event {
  double t;  // s
  Act act;
};

struct HoldRun {
  double speed_at_cmd = 0;     // m/s over ground at the first event
  double max_distance = 0;     // m from the first event's position, until a RESUME (or the end)
  double final_distance = 0;   // m, at the RESUME (or the end)
  double max_thrust_step = 0;  // largest change of a thruster command between two commands,
                               // within 5 s after each event (normalised, [-1, 1] range)
  double switch_step = 0;      // the same in thrust (c|c|) within 0.25 s of each change of the
                               // mixer's source
                               // after the first event (the hand-over)
  double max_thrust_step_before = 0;   // the same over the 10 s before the first event
  bool gate_active_throughout = true;  // the mixer's gate ACTIVE from the start to the end
  std::string reason;                  // the arbitration's reason at the end
  std::int8_t source = -1;             // and its source
  bool armed_at_end = true;
  double max_command_at_end = 0;  // |thruster command| at the end
  bool completed = false;         // the follower reported the path complete
  double disarmed_after_s = -1;   // s from the first event to the arm state saying disarmed
  std::int64_t dropped_repeats = 0;
};

HoldRun run(const std::vector<Event>& events, double end_s, bool can_hold = true) {
  const PlantSpec& spec = plants()[0];  // the Otter, full stack
  mission::Mission m;
  m.name = "hold";
  m.start = mission::MissionPoint{0, 0, true, 0};
  m.waypoints = {{0, 0, false, 0}, {150, 0, false, 0}};
  auto plant = spec.make(m, 0.3, deg_to_rad(30));
  const auto groot = config::Value::load_file(source_path(spec.guidance_file));
  guidance::PathFollowerNode follower(guidance::load_follower_node_params(groot));
  const auto croot = source_path(spec.control_file);
  auto vparams = control::load_velocity_pid_node_params(config::Value::load_file(croot));
  vparams.arbiter.hold_position = can_hold;
  control::VelocityPidNode vpid(vparams);
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  mission::MissionNode mission(m, 5, kUsPerSecond);  // arms, STARTs, repeats path 5 every 1 s
  LockstepExecutor ex(0);
  for (auto& p : plant) ex.add(*p);
  ex.add(mission);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);

  HoldRun r;
  const double t0 = events.front().t;
  double resume_t = end_s;
  for (const auto& e : events)
    if (e.act == Act::kResume) resume_t = e.t;
  bool have_origin = false, started = false;
  double on = 0, oe = 0;
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  thruster_command_t cmd{}, last{};
  bool have_last = false;
  double switched_at = -1e9;
  arbitration_t arb{};
  arm_state_t arm{};
  path_progress_t pr{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == spec.pose_channel && o.decode(d, 0, n) == n) {
      if (!have_origin && ts >= t0) {
        have_origin = true;
        on = o.position[0];
        oe = o.position[1];
        r.speed_at_cmd = std::hypot(o.velocity[0], o.velocity[1]);
      }
      if (have_origin && ts <= resume_t) {
        r.final_distance = std::hypot(o.position[0] - on, o.position[1] - oe);
        r.max_distance = std::max(r.max_distance, r.final_distance);
      }
    } else if (ch == channels::kThrusterCommand && cmd.decode(d, 0, n) == n) {
      started = started || cmd.gate == thruster_command_t::GATE_ACTIVE;
      if (started && cmd.gate != thruster_command_t::GATE_ACTIVE) r.gate_active_throughout = false;
      if (have_last) {
        double step = 0, thrust_step = 0;
        for (int i = 0; i < cmd.n_thrusters; ++i) {
          const double c = cmd.command[static_cast<std::size_t>(i)];
          const double l = last.command[static_cast<std::size_t>(i)];
          step = std::max(step, std::abs(c - l));
          thrust_step = std::max(thrust_step, std::abs(c * std::abs(c) - l * std::abs(l)));
        }
        for (const auto& e : events)
          if (ts >= e.t && ts <= e.t + 5) r.max_thrust_step = std::max(r.max_thrust_step, step);
        if (ts > t0 && cmd.source != last.source) switched_at = ts;
        if (ts <= switched_at + 0.25) r.switch_step = std::max(r.switch_step, thrust_step);
        if (ts >= t0 - 10 && ts < t0)
          r.max_thrust_step_before = std::max(r.max_thrust_step_before, step);
      }
      last = cmd;
      have_last = true;
      r.max_command_at_end = 0;
      for (int i = 0; i < cmd.n_thrusters; ++i)
        r.max_command_at_end =
            std::max(r.max_command_at_end, std::abs(cmd.command[static_cast<std::size_t>(i)]));
    } else if (ch == channels::kArbitration && arb.decode(d, 0, n) == n) {
      r.source = arb.active_source;
      r.reason = arb.reason;
    } else if (ch == channels::kArmState && arm.decode(d, 0, n) == n) {
      r.armed_at_end = arm.armed;
      if (!arm.armed && ts > t0 && r.disarmed_after_s < 0) r.disarmed_after_s = ts - t0;
    } else if (ch == channels::kPathProgress && pr.decode(d, 0, n) == n) {
      r.completed = r.completed || pr.complete;
    }
  });

  std::int64_t id = 100;
  for (const auto& e : events) {
    const TimeUs t = from_seconds(e.t);
    if (e.act == Act::kCancel) {
      path_t cancel{};
      cancel.utime = t;
      cancel.path_id = 6;  // a planner's cancel
      ex.inject(channels::kPath, cancel, t);
      continue;
    }
    mission_command_t c{};
    c.utime = t;
    c.command_id = ++id;
    c.source = "hold-test";
    c.command = e.act == Act::kPause    ? mission_command_t::PAUSE
                : e.act == Act::kResume ? mission_command_t::RESUME
                : e.act == Act::kAbort  ? mission_command_t::ABORT
                                        : mission_command_t::RELEASE;
    ex.inject(channels::kMissionCommand, c, t);
  }
  ex.run_until(from_seconds(end_s));
  r.dropped_repeats = follower.counter_value("paths.dropped_repeats");
  std::printf(
      "hold: speed at the event %.2f m/s, max distance %.2f m, at the end %.2f m, thrust step "
      "at the hand-over %.3f, within 5 s %.3f (before %.3f), gate active %d, source %d (%s), "
      "armed %d, disarmed after %.2f s\n",
      r.speed_at_cmd, r.max_distance, r.final_distance, r.switch_step, r.max_thrust_step,
      r.max_thrust_step_before, r.gate_active_throughout, r.source, r.reason.c_str(),
      r.armed_at_end, r.disarmed_after_s);
  return r;
}

// The stopping distance: from 1.5 m/s the station keeper's D term (kd 80 N/(m/s): 120 N astern)
// and the hull's drag stop the boat; the thrust blends from the velocity PID's over blend_s
// (1 s, no step), so the boat runs on ~1 m while the blend turns the thrust round. Measured on
// this rig: 1.36 m past the cancel point, then it holds within that, facing into the current.
constexpr double kStoppingDistance = 2.0;  // m: the bound asserted (measured 1.72 m)
// The largest change of a thruster's normalised thrust c|c| (the ESC's thrust is quadratic in the
// command c) between two mixer commands in the 0.25 s after the source changes: the hand-over
// blends. In thrust, not in command: near zero thrust a 6 N change (5 % of full) is a command
// step of 0.35 (-0.137 -> 0.216, measured at the resume with the Otter's station keeping at ki 10,
// i_limit 30 N), though the wrench blends smoothly (X 26.2 -> 36.9 N, N 11.3 -> 10.2 N m).
// Measured in thrust: 0.064 at that resume. The velocity PID's steady commands change by 0.004
// per command. Later in the stop the station keeper's own law,
// braking from 1.5 m/s and turning into the current with one thruster saturated, changes a
// command by up to 0.64 in 50 ms: its tuning, not the hand-over.
constexpr double kHandOverStep = 0.15;

TEST(Hold, CancelAtSpeedHoldsWhereTheBoatWasInACurrent) {
  const auto r = run({{40, Act::kCancel}}, 100);
  EXPECT_GT(r.speed_at_cmd, 1.3);  // at cruise
  EXPECT_LT(r.max_distance, kStoppingDistance);
  EXPECT_LT(r.final_distance, 1.0);  // 60 s later, back near the cancel point
  EXPECT_TRUE(r.gate_active_throughout);
  EXPECT_EQ(r.source, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_NE(r.reason.find("holding position"), std::string::npos) << r.reason;
  EXPECT_TRUE(r.armed_at_end);
  EXPECT_LT(r.switch_step, kHandOverStep);  // blended hand-over: no thrust step
  EXPECT_FALSE(r.completed);                // the mission's repeats did not restart the path
}

TEST(Hold, AbortHoldsAndTheMissionsRepeatsAreIgnored) {
  const auto r = run({{40, Act::kAbort}}, 100);
  EXPECT_LT(r.max_distance, kStoppingDistance);
  EXPECT_LT(r.final_distance, 1.0);
  EXPECT_TRUE(r.gate_active_throughout);
  EXPECT_EQ(r.source, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_GE(r.dropped_repeats, 55);  // one a second for 60 s
  EXPECT_FALSE(r.completed);
  EXPECT_LT(r.switch_step, kHandOverStep);
}

TEST(Hold, PauseHoldsAndResumeCompletesThePath) {
  const auto r = run({{40, Act::kPause}, {60, Act::kResume}}, 160);
  EXPECT_LT(r.max_distance, kStoppingDistance);  // over the 20 s of the pause
  EXPECT_TRUE(r.gate_active_throughout);
  EXPECT_TRUE(r.completed);  // 150 m: resumed from where it held
  EXPECT_LT(r.switch_step, kHandOverStep);
}

TEST(Hold, ReleaseDisarms) {
  const auto r = run({{40, Act::kRelease}}, 50);
  EXPECT_FALSE(r.armed_at_end);
  EXPECT_GE(r.disarmed_after_s, 0.0);
  EXPECT_LT(r.disarmed_after_s, 0.2);  // the mixer's request on the release, then tiller-esc
  EXPECT_EQ(r.max_command_at_end, 0.0);
}

TEST(Hold, AVehicleThatCannotHoldGoesNeutralThenDisarms) {
  const auto r = run({{40, Act::kCancel}}, 50, false);
  EXPECT_EQ(r.source, wrench_t::SOURCE_NONE);
  EXPECT_NE(r.reason.find("cannot hold"), std::string::npos) << r.reason;
  EXPECT_EQ(r.max_command_at_end, 0.0);
  EXPECT_FALSE(r.armed_at_end);
  EXPECT_NEAR(r.disarmed_after_s, 3.0, 0.2);  // safety.disarm_after_s
}

}  // namespace
}  // namespace tiller::test
