// The controllers' integrators follow the mixer's safety gate (control/integrator_gate.hpp,
// issue 12): through the node classes, a velocity PID and a station keeper in control with a
// standing error, the mixer's TILLER_THRUSTER_COMMAND saying DISARMED for 4 s: the integral stays
// exactly 0 (the old code ran the yaw integral to its 20 N m limit in 2 s). When the gate turns
// ACTIVE with the controller's source, the first output has zero integral (no step) and the
// integral then grows by ki * e * dt per odometry step, hand-computed. WAIT_NEUTRAL resets,
// INPUT_LOST and another source freeze, no mixer at all freezes.
// And the hold (docs/safety.md): the arbiter hands a stopped path (cancel, abort, pause) or stale
// guidance to station keeping once a path was followed (neutral on a vehicle that cannot hold);
// the station keeper in control without a target holds where the vehicle was when it took
// control, re-captured while the gate says disarmed.
#include <gtest/gtest.h>

#include <tiller/pid_terms_t.hpp>

#include <cmath>
#include <string>
#include <tiller/thruster_command_t.hpp>

#include "control/arbiter.hpp"
#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::control {
namespace {

const std::string kOtter = std::string(TILLER_SOURCE_DIR) + "/config/control/otter.yaml";
constexpr TimeUs kStep = 50'000;  // 20 Hz odometry, mixer commands and controller ticks

thruster_command_t gate_cmd(TimeUs t, std::int8_t gate, std::int8_t source) {
  thruster_command_t c{};
  c.utime = t;
  c.armed = gate != thruster_command_t::GATE_DISARMED;
  c.gate = gate;
  c.source = gate == thruster_command_t::GATE_ACTIVE ? source : wrench_t::SOURCE_NONE;
  c.arm_allowed = true;
  return c;
}

// What the mixer says from t0 to t1 (exclusive), at 20 Hz.
void mixer_says(LockstepExecutor& ex, std::int8_t gate, std::int8_t source, TimeUs t0, TimeUs t1) {
  for (TimeUs t = t0; t < t1; t += kStep)
    ex.inject(channels::kThrusterCommand, gate_cmd(t, gate, source), t);
}

// The velocity PID in waypointing, in control (a path in progress), heading 0, still, with a
// setpoint of 1 m/s north and a target heading of 1 rad: surge error 1 m/s, yaw-rate setpoint
// clamp(heading_kp * 1, max_yaw_rate) = 0.5 rad/s, error 0.5 rad/s.
struct VelocityRig {
  VelocityPidNodeParams p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  VelocityPidNode node{p};
  LockstepExecutor ex{0};
  pid_terms_t terms{};
  std::vector<pid_terms_t> log;  // every published terms message, in order
  explicit VelocityRig(TimeUs end) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kPidVelocity && terms.decode(d, 0, n) == n) log.push_back(terms);
    });
    controller_mode_t m{};
    m.mode = controller_mode_t::WAYPOINTING;
    m.source = "test";
    ex.inject(channels::kMode, m, 0);
    for (TimeUs t = 0; t < end; t += kStep) {
      odometry_t o{};
      o.valid = odometry_t::VALID_ALL;
      o.utime = t;
      ex.inject(channels::kOdometry, o, t);
      velocity_setpoint_t sp{};
      sp.utime = t;
      sp.frame = velocity_setpoint_t::FRAME_NED;
      sp.active = true;
      sp.velocity[0] = 1.0;
      sp.heading_valid = true;
      sp.target_heading = 1.0;
      ex.inject(channels::kVelocitySetpoint, sp, t);
      path_progress_t pr{};
      pr.utime = t;
      pr.path_id = 1;
      pr.segment = 0;
      pr.n_waypoints = 2;
      pr.distance_to_goal = 50.0;
      ex.inject(channels::kPathProgress, pr, t);
    }
  }
};

TEST(IntegratorGate, VelocityPidDoesNotIntegrateWhileDisarmedAndStartsFromZero) {
  VelocityRig r(6'000'000);
  mixer_says(r.ex, thruster_command_t::GATE_DISARMED, wrench_t::SOURCE_NONE, 0, 4'000'000);
  mixer_says(r.ex, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_VELOCITY_PID, 4'000'000,
             6'000'000);
  r.ex.run_until(3'990'000);
  ASSERT_EQ(r.node.decision().source, wrench_t::SOURCE_VELOCITY_PID);  // in control throughout
  EXPECT_EQ(r.terms.setpoint[0], 1.0);
  EXPECT_EQ(r.terms.measured[0], 0.0);
  for (const auto& t : r.log) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(t.i[k], 0.0) << "axis " << k << " at " << t.utime;  // 4 s disarmed: exactly 0
      EXPECT_TRUE(t.integrator_frozen[k]);
    }
  }
  // The first tick that sees the ACTIVE command (sent at 4.0 s; at one instant ticks run before
  // messages, so the tick at 4.05 s): feed-forward + P + one step of integral, ki * e * 0.05 s,
  // not a wound-up integral (the old code: surge 60 N/(m s) * 1 m/s * 4 s, at its 80 N limit;
  // yaw at its 20 N m limit).
  r.ex.run_until(4'050'000);
  const auto& g = r.p.pid;
  EXPECT_NEAR(r.terms.i[0], g.surge.ki * 1.0 * 0.05, 1e-12);  // 3 N
  EXPECT_NEAR(r.terms.i[2], g.yaw.ki * 0.5 * 0.05, 1e-12);    // 0.5 N m
  EXPECT_NEAR(r.terms.output[0], g.surge.k_drag * 1.0 + g.surge.k_error * 1.0 + 3.0, 1e-9);
  EXPECT_NEAR(r.terms.feed_forward[2] + r.terms.p[2],
              g.yaw.k_drag * 0.5 + g.yaw.k_drag_quad * 0.25 + g.yaw.k_error * 0.5, 1e-9);
  EXPECT_EQ(r.terms.output[2], g.yaw.max_output);  // 42.65 * 0.5 + 426.5 * 0.25 + 30 > 90
  EXPECT_FALSE(r.terms.integrator_frozen[0]);
  r.ex.run_until(4'550'000);                                 // 10 more steps of 0.05 s
  EXPECT_NEAR(r.terms.i[0], g.surge.ki * 1.0 * 0.55, 1e-9);  // 60 * 1 * 0.55 = 33 N
  EXPECT_NEAR(r.terms.i[2], g.yaw.ki * 0.5 * 0.55, 1e-9);    // 20 * 0.5 * 0.55 = 5.5 N m
}

TEST(IntegratorGate, VelocityPidResetsWhenDisarmedFreezesOnInputLostOrAnotherSource) {
  VelocityRig r(5'000'000);
  const auto pid = wrench_t::SOURCE_VELOCITY_PID;
  mixer_says(r.ex, thruster_command_t::GATE_ACTIVE, pid, 0, 1'000'000);
  mixer_says(r.ex, thruster_command_t::GATE_INPUT_LOST, pid, 1'000'000, 2'000'000);
  mixer_says(r.ex, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_STATION_KEEP, 2'000'000,
             3'000'000);
  mixer_says(r.ex, thruster_command_t::GATE_WAIT_NEUTRAL, pid, 3'000'000, 4'000'000);
  r.ex.run_until(1'020'000);
  const double built = r.terms.i[0];
  // Ticks 0.10 .. 1.00 s (0.05 s is the entry tick, dt 0): 19 steps of 60 * 1 m/s * 0.05 s.
  EXPECT_NEAR(built, 60 * 1.0 * 0.05 * 19, 1e-9);
  r.ex.run_until(1'950'000);
  EXPECT_EQ(r.terms.i[0], built);  // INPUT_LOST: frozen, kept for the input's return
  r.ex.run_until(2'950'000);
  EXPECT_EQ(r.terms.i[0], built);  // another source allocated: frozen
  r.ex.run_until(3'950'000);
  EXPECT_EQ(r.terms.i[0], 0.0);  // WAIT_NEUTRAL (a new arming): reset, the start is from zero
  r.ex.run_until(4'950'000);
  EXPECT_EQ(r.terms.i[0], 0.0);  // the mixer silent (stopped): frozen at what it was
}

// The station keeper in control of a target 1 m north, the vehicle still at the origin heading 0.
TEST(IntegratorGate, StationKeeperDoesNotIntegrateWhileDisarmedAndStartsFromZero) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  p.pid.weathervane = false;
  StationKeepNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  pid_terms_t terms{};
  double max_abs_i = 0;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    if (ch == channels::kPidStation && terms.decode(d, 0, n) == n && t < 4'000'000)
      for (double i : terms.i) max_abs_i = std::max(max_abs_i, std::abs(i));
  });
  for (TimeUs t = 0; t < 6'000'000; t += kStep) {
    station_target_t st{};
    st.utime = t;
    st.active = true;
    st.position[0] = 1.0;
    st.heading_valid = true;
    ex.inject(channels::kStationTarget, st, t);
    arbitration_t arb{};
    arb.utime = t;
    arb.mode = controller_mode_t::WAYPOINTING;
    arb.active_source = wrench_t::SOURCE_STATION_KEEP;
    arb.reason = "test";
    ex.inject(channels::kArbitration, arb, t);
    odometry_t o{};
    o.valid = odometry_t::VALID_ALL;
    o.utime = t;
    ex.inject(channels::kOdometry, o, t);
  }
  mixer_says(ex, thruster_command_t::GATE_DISARMED, wrench_t::SOURCE_NONE, 0, 4'000'000);
  mixer_says(ex, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_STATION_KEEP, 4'000'000,
             6'000'000);
  ex.run_until(3'990'000);
  ASSERT_TRUE(node.active());
  EXPECT_EQ(max_abs_i, 0.0);  // the old code: 10 N/(m s) * 1 m * 4 s = 40 N
  EXPECT_DOUBLE_EQ(terms.p[0], p.pid.x.kp * 1.0);
  ex.run_until(4'050'000);  // the first tick that sees ACTIVE: P + one step of integral
  EXPECT_NEAR(terms.i[0], p.pid.x.ki * 1.0 * 0.05, 1e-12);  // 10 N/(m s) * 1 m * 0.05 s = 0.5 N
  EXPECT_NEAR(terms.output[0], p.pid.x.kp * 1.0 + p.pid.x.ki * 1.0 * 0.05, 1e-9);
  ex.run_until(4'550'000);
  EXPECT_NEAR(terms.i[0], p.pid.x.ki * 1.0 * 0.55, 1e-9);  // 10 * 1 m * 0.55 s = 5.5 N
}

TEST(Hold, TheArbiterHoldsAStoppedPathOrLostGuidanceOnceAPathWasFollowed) {
  for (const bool can_hold : {true, false}) {
    SCOPED_TRACE(can_hold);
    Arbiter a({controller_mode_t::WAYPOINTING, 2.0, 0.5, can_hold});
    const std::int8_t hold = can_hold ? wrench_t::SOURCE_STATION_KEEP : wrench_t::SOURCE_NONE;
    ArbiterInput in;
    in.mode = controller_mode_t::WAYPOINTING;
    in.progress_fresh = true;
    EXPECT_EQ(a.decide(in).source, wrench_t::SOURCE_NONE);  // no path yet: neutral
    in.path_active = true;
    in.distance_to_goal = 30;
    EXPECT_EQ(a.decide(in).source, wrench_t::SOURCE_VELOCITY_PID);
    in.path_active = false;  // cancelled, aborted or paused
    auto d = a.decide(in);
    EXPECT_EQ(d.source, hold);
    EXPECT_NE(std::string(d.reason).find(can_hold ? "holding position" : "cannot hold"),
              std::string::npos)
        << d.reason;
    in.path_active = true;  // resumed
    EXPECT_EQ(a.decide(in).source, wrench_t::SOURCE_VELOCITY_PID);
    in.setpoint_fresh = false;  // the follower's setpoints stale
    d = a.decide(in);
    EXPECT_EQ(d.source, hold);
    EXPECT_NE(std::string(d.reason).find("guidance lost"), std::string::npos) << d.reason;
    in.setpoint_fresh = true;
    in.progress_fresh = false;  // the follower gone
    EXPECT_EQ(a.decide(in).source, hold);
    in.mode = controller_mode_t::MANUAL_OPEN_LOOP;  // leaving waypointing forgets the path
    EXPECT_EQ(a.decide(in).source, wrench_t::SOURCE_MANUAL_DEMAND);
    in.mode = controller_mode_t::WAYPOINTING;
    in.progress_fresh = true;
    in.path_active = false;
    EXPECT_EQ(a.decide(in).source, wrench_t::SOURCE_NONE);
  }
}

// Station keeping in control with no target, the vehicle at (3, 4) m heading 0.5 rad.
TEST(Hold, StationKeeperWithoutATargetHoldsWhereTheVehicleWas) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  p.pid.weathervane = false;
  StationKeepNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  wrench_t ws{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == channels::kWrenchStation) ws.decode(d, 0, n);
  });
  // Disarmed until 2 s, the vehicle drifting north from (3, 4) at 0.5 m/s until 1.5 s, then at
  // (4, 4); ACTIVE from 2 s, still at (4, 4) until 3 s, then at (5, 4): 1 m north of the hold.
  for (TimeUs t = 0; t < 4'000'000; t += kStep) {
    arbitration_t arb{};
    arb.utime = t;
    arb.mode = controller_mode_t::WAYPOINTING;
    arb.active_source = wrench_t::SOURCE_STATION_KEEP;
    arb.reason = "test";
    ex.inject(channels::kArbitration, arb, t);
    odometry_t o{};
    o.valid = odometry_t::VALID_ALL;
    o.utime = t;
    o.position[0] = t < 1'500'000 ? 3.0 + 0.5 * to_seconds(t) : t < 3'000'000 ? 4.0 : 5.0;
    o.position[1] = 4.0;
    o.orientation[2] = 0.5;
    ex.inject(channels::kOdometry, o, t);
  }
  mixer_says(ex, thruster_command_t::GATE_DISARMED, wrench_t::SOURCE_NONE, 0, 2'000'000);
  mixer_says(ex, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_STATION_KEEP, 2'000'000,
             4'000'000);
  ex.run_until(2'950'000);
  ASSERT_TRUE(node.holding_here());
  EXPECT_TRUE(ws.valid);  // a hold, not an idle keeper
  // Re-captured while disarmed: held at (4, 4), where the vehicle was at the start (not (3, 4),
  // where it was when station keeping took control); still there.
  EXPECT_NEAR(node.terms().measured[0], 0.0, 1e-9);
  EXPECT_NEAR(node.terms().measured[1], 0.0, 1e-9);
  EXPECT_NEAR(node.terms().setpoint[2], 0.5, 1e-12);  // and its heading then
  ex.run_until(3'500'000);
  // 1 m north of the hold point, heading 0.5: body position (cos 0.5, -sin 0.5) m from it, so a
  // P force of kp back along it (no D: the odometry's velocity is 0).
  EXPECT_NEAR(node.terms().measured[0], std::cos(0.5), 1e-9);
  EXPECT_NEAR(node.terms().measured[1], -std::sin(0.5), 1e-9);
  EXPECT_LT(ws.tau[0], -0.8 * p.pid.x.kp * std::cos(0.5));
}

}  // namespace
}  // namespace tiller::control
