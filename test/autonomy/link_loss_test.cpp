// Autonomy link loss (issue 12, "what to build" 2), in lockstep through the node classes:
//   * stale setpoints with fresh odometry (the path follower stops publishing at 40 s, at speed,
//     on the full Otter stack in a 0.3 m/s current): the arbiter's hold, station keeping where
//     the boat is, within the stopping distance, armed, the gate ACTIVE, no thrust step;
//   * the same on a vehicle that cannot hold (arbiter.hold_position false): neutral at once, the
//     mixer's disarm after safety.disarm_after_s (3 s);
//   * stale odometry (nothing to hold on): mixer + ESC + both controllers with odometry, setpoints
//     and progress given by the test, odometry stopping at 10 s: the controllers' wrenches turn
//     invalid after odometry_timeout_s (0.5 s), the mixer's gate goes INPUT_LOST (neutral), and
//     its disarm request follows safety.disarm_after_s later: disarmed at 13.5 s.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/angles.hpp"
#include "esc/esc_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mixer/mixer_node.hpp"
#include "plants.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {
namespace {

// A path follower that dies at `stop`: it publishes nothing from then on.
class StoppingFollower : public guidance::PathFollowerNode {
 public:
  StoppingFollower(const guidance::FollowerNodeParams& p, TimeUs stop)
      : PathFollowerNode(p), stop_(stop) {}
  void on_tick(TimeUs now) override {
    if (now < stop_) PathFollowerNode::on_tick(now);
  }

 private:
  TimeUs stop_;
};

struct LossRun {
  double speed_at_loss = 0;   // m/s over ground
  double max_distance = 0;    // m from where the boat was at the loss
  double final_distance = 0;  // m
  double switch_step = 0;     // normalised: the largest change between two mixer commands within
                              // 0.25 s after the source changes (the hand-over)
  bool gate_active_throughout = true;
  std::int8_t source = -1;
  std::string reason;
  bool armed_at_end = true;
  double disarmed_after_s = -1;   // s from the loss
  double max_command_at_end = 0;  // |thruster command|
};

LossRun run_follower_loss(double loss_s, double end_s, bool can_hold) {
  const PlantSpec& spec = plants()[0];  // the Otter, full stack
  mission::Mission m;
  m.name = "loss";
  m.start = mission::MissionPoint{0, 0, true, 0};
  m.waypoints = {{0, 0, false, 0}, {150, 0, false, 0}};
  auto plant = spec.make(m, 0.3, deg_to_rad(30));
  const auto groot = config::Value::load_file(source_path(spec.guidance_file));
  StoppingFollower follower(guidance::load_follower_node_params(groot), from_seconds(loss_s));
  const auto croot = source_path(spec.control_file);
  auto vparams = control::load_velocity_pid_node_params(config::Value::load_file(croot));
  vparams.arbiter.hold_position = can_hold;
  control::VelocityPidNode vpid(vparams);
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  mission::MissionNode mission(m, 5, kUsPerSecond);
  LockstepExecutor ex(0);
  for (auto& p : plant) ex.add(*p);
  ex.add(mission);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);

  LossRun r;
  bool have_origin = false, started = false, have_last = false;
  double switched_at = -1e9;
  double on = 0, oe = 0;
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  thruster_command_t cmd{}, last{};
  arbitration_t arb{};
  arm_state_t arm{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == spec.pose_channel && o.decode(d, 0, n) == n) {
      if (!have_origin && ts >= loss_s) {
        have_origin = true;
        on = o.position[0];
        oe = o.position[1];
        r.speed_at_loss = std::hypot(o.velocity[0], o.velocity[1]);
      }
      if (have_origin) {
        r.final_distance = std::hypot(o.position[0] - on, o.position[1] - oe);
        r.max_distance = std::max(r.max_distance, r.final_distance);
      }
    } else if (ch == channels::kThrusterCommand && cmd.decode(d, 0, n) == n) {
      started = started || cmd.gate == thruster_command_t::GATE_ACTIVE;
      if (started && cmd.gate != thruster_command_t::GATE_ACTIVE) r.gate_active_throughout = false;
      if (have_last && ts > loss_s && cmd.source != last.source) switched_at = ts;
      r.max_command_at_end = 0;
      for (int i = 0; i < cmd.n_thrusters; ++i) {
        const auto k = static_cast<std::size_t>(i);
        r.max_command_at_end = std::max(r.max_command_at_end, std::abs(cmd.command[k]));
        if (have_last && ts <= switched_at + 0.25)
          r.switch_step = std::max(r.switch_step, std::abs(cmd.command[k] - last.command[k]));
      }
      last = cmd;
      have_last = true;
    } else if (ch == channels::kArbitration && arb.decode(d, 0, n) == n) {
      r.source = arb.active_source;
      r.reason = arb.reason;
    } else if (ch == channels::kArmState && arm.decode(d, 0, n) == n) {
      r.armed_at_end = arm.armed;
      if (!arm.armed && ts > loss_s && r.disarmed_after_s < 0) r.disarmed_after_s = ts - loss_s;
    }
  });
  ex.run_until(from_seconds(end_s));
  std::printf(
      "follower lost: speed %.2f m/s, max distance %.2f m, at the end %.2f m, thrust step at the "
      "hand-over %.3f, "
      "source %d (%s), armed %d, disarmed after %.2f s\n",
      r.speed_at_loss, r.max_distance, r.final_distance, r.switch_step, r.source, r.reason.c_str(),
      r.armed_at_end, r.disarmed_after_s);
  return r;
}

TEST(LinkLoss, StaleSetpointsWithFreshOdometryHoldPosition) {
  const auto r = run_follower_loss(40, 100, true);
  EXPECT_GT(r.speed_at_loss, 1.3);
  // The stopping distance (hold_test: 1.72 m) plus 0.5 s at speed before the setpoints count as
  // stale (input_timeout_s). Measured 2.17 m.
  EXPECT_LT(r.max_distance, 2.5);
  EXPECT_LT(r.final_distance, 1.0);
  EXPECT_TRUE(r.gate_active_throughout);
  EXPECT_TRUE(r.armed_at_end);
  EXPECT_EQ(r.source, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_NE(r.reason.find("guidance lost"), std::string::npos) << r.reason;
  EXPECT_LT(r.switch_step, 0.15);  // blended hand-over (hold_test)
}

TEST(LinkLoss, StaleSetpointsOnAVehicleThatCannotHoldGiveNeutralThenDisarm) {
  const auto r = run_follower_loss(40, 50, false);
  EXPECT_EQ(r.source, wrench_t::SOURCE_NONE);
  EXPECT_EQ(r.max_command_at_end, 0.0);
  EXPECT_FALSE(r.armed_at_end);
  // Setpoints stale 0.5 s after the last (input_timeout_s), then safety.disarm_after_s (3 s).
  EXPECT_NEAR(r.disarmed_after_s, 3.5, 0.2);
}

// Odometry that stops: no sim, the test gives odometry (still, at the origin), a path in
// progress and a setpoint; mixer + ESC (sim backend) + both controllers for the Otter.
TEST(LinkLoss, StaleOdometryGivesNeutralThenDisarm) {
  MixerNode mixer(source_path("config/mixer/otter.yaml"));
  EscNode esc(source_path("config/esc/otter_sim.yaml"));
  const auto croot = source_path("config/control/otter.yaml");
  control::VelocityPidNode vpid(
      control::load_velocity_pid_node_params(config::Value::load_file(croot)));
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  LockstepExecutor ex(0);
  ex.add(esc);
  ex.add(mixer);
  ex.add(vpid);
  ex.add(skeep);
  double neutral_at = -1, input_lost_at = -1, disarmed_at = -1, armed_at = -1;
  thruster_command_t cmd{};
  arm_state_t arm{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == channels::kThrusterCommand && cmd.decode(d, 0, n) == n && ts > 10) {
      bool zero = true;
      for (double c : cmd.command) zero = zero && c == 0.0;
      if (zero && neutral_at < 0) neutral_at = ts;
      if (cmd.gate == thruster_command_t::GATE_INPUT_LOST && input_lost_at < 0) input_lost_at = ts;
    } else if (ch == channels::kArmState && arm.decode(d, 0, n) == n) {
      if (arm.armed && armed_at < 0) armed_at = ts;
      if (!arm.armed && armed_at >= 0 && disarmed_at < 0) disarmed_at = ts;
    }
  });
  controller_mode_t mode{};
  mode.mode = controller_mode_t::WAYPOINTING;
  mode.source = "test";
  ex.inject(channels::kMode, mode, 0);
  arm_request_t a{};
  a.arm = true;
  a.source = "test";
  ex.inject(channels::kArmRequest, a, 100'000);
  mission_command_t go{};
  go.utime = 500'000;
  go.command_id = 1;
  go.command = mission_command_t::START;
  go.source = "test";
  ex.inject(channels::kMissionCommand, go, 500'000);
  for (TimeUs t = 0; t < 20'000'000; t += 50'000) {
    if (t < 10'000'000) {
      odometry_t o{};
      o.valid = odometry_t::VALID_ALL;
      o.utime = t;
      ex.inject(channels::kOdometry, o, t);
    }
    velocity_setpoint_t sp{};
    sp.utime = t;
    sp.active = true;
    sp.velocity[0] = 1.0;
    ex.inject(channels::kVelocitySetpoint, sp, t);
    path_progress_t pr{};
    pr.utime = t;
    pr.path_id = 1;
    pr.segment = 0;
    pr.n_waypoints = 2;
    pr.distance_to_goal = 50;
    ex.inject(channels::kPathProgress, pr, t);
  }
  ex.run_until(20'000'000);
  std::printf(
      "odometry lost at 10 s: gate INPUT_LOST at %.2f s, neutral at %.2f s, disarmed at "
      "%.2f s (armed at %.2f s)\n",
      input_lost_at, neutral_at, disarmed_at, armed_at);
  EXPECT_GE(armed_at, 0.0);
  EXPECT_NEAR(input_lost_at, 10.5, 0.06);  // odometry_timeout_s: the wrench turns invalid
  EXPECT_NEAR(neutral_at, 10.5, 0.06);
  EXPECT_NEAR(disarmed_at, 13.5, 0.1);  // + safety.disarm_after_s
}

}  // namespace
}  // namespace tiller::test
