// The velocity-PID node (with the arbiter) and the station-keep node: arbitration on the bus,
// integrators reset on entry and frozen by the mixer's status, NaN odometry dropped and
// counted, odometry that stops -> neutral or hold by config within the freshness limit (both
// nodes), a NaN wrench from the other controller dropped and counted; and, table-driven, a
// malformed message of each input type (core/message_checks.hpp) dropped, counted under its
// counter, and the node's outputs bit-identical to the same run without it.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include <cmath>
#include <functional>
#include <set>
#include <vector>

#include "bad_values.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::control {
namespace {

const std::string kOtter = std::string(TILLER_SOURCE_DIR) + "/config/control/otter.yaml";

odometry_t odom(TimeUs t, double n = 0, double e = 0, double psi = 0, double u = 0) {
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  o.utime = t;
  o.position[0] = n;
  o.position[1] = e;
  o.orientation[2] = psi;
  o.velocity[0] = u;
  return o;
}

controller_mode_t mode(std::int8_t m) {
  controller_mode_t c{};
  c.mode = m;
  c.source = "test";
  return c;
}

struct Bus {
  wrench_t wv{}, ws{};
  arbitration_t arb{};
  pid_terms_t pv{};
  int n_arb = 0;
  std::int64_t stale = 0;  // the node's stale counter at the end
};

void watch(LockstepExecutor& ex, Bus& b) {
  ex.observe([&b](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == channels::kWrenchVelocity) b.wv.decode(d, 0, n);
    if (ch == channels::kWrenchStation) b.ws.decode(d, 0, n);
    if (ch == channels::kPidVelocity) b.pv.decode(d, 0, n);
    if (ch == channels::kArbitration) {
      b.arb.decode(d, 0, n);
      ++b.n_arb;
    }
  });
}

// The mixer's thruster command: gate (thruster_command_t GATE_*) and the source it allocated.
thruster_command_t gate_cmd(TimeUs t, std::int8_t gate, std::int8_t source) {
  thruster_command_t c{};
  c.utime = t;
  c.armed = gate == thruster_command_t::GATE_ACTIVE;
  c.gate = gate;
  c.source = source;
  c.arm_allowed = true;
  return c;
}

// An armed, started mixer allocating `source`, at 20 Hz from t0 to t1 (exclusive): the
// controllers integrate only then (control/integrator_gate.hpp).
void applied(LockstepExecutor& ex, std::int8_t source, TimeUs t0, TimeUs t1) {
  for (TimeUs t = t0; t < t1; t += 50'000)
    ex.inject(channels::kThrusterCommand, gate_cmd(t, thruster_command_t::GATE_ACTIVE, source), t);
}

// Feeds odometry at 20 Hz from t0 to t1 (exclusive).
void feed(LockstepExecutor& ex, TimeUs t0, TimeUs t1, double u = 0) {
  for (TimeUs t = t0; t < t1; t += 50'000) ex.inject(channels::kOdometry, odom(t, 0, 0, 0, u), t);
}

TEST(VelocityPidNode, ManualClosedLoopTracksTheManualCommand) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  VelocityPidNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  ex.run_until(100'000);
  EXPECT_EQ(b.arb.active_source, wrench_t::SOURCE_MANUAL_DEMAND);  // default mode
  ex.inject(channels::kMode, mode(controller_mode_t::MANUAL_CLOSED_LOOP), 110'000);
  manual_velocity_cmd_t m{};
  m.velocity[0] = 1.0;
  m.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
  m.valid = true;
  for (TimeUs t = 110'000; t < 1'000'000; t += 50'000) {
    m.utime = t;
    ex.inject(channels::kManualVelocity, m, t);
  }
  feed(ex, 110'000, 1'000'000, 0.4);
  applied(ex, wrench_t::SOURCE_VELOCITY_PID, 110'000, 1'000'000);
  ex.run_until(900'000);
  EXPECT_EQ(b.arb.active_source, wrench_t::SOURCE_VELOCITY_PID);
  EXPECT_EQ(b.arb.mode, controller_mode_t::MANUAL_CLOSED_LOOP);
  EXPECT_TRUE(b.wv.valid);
  EXPECT_DOUBLE_EQ(b.pv.feed_forward[0], p.pid.surge.k_drag * 1.0);
  EXPECT_DOUBLE_EQ(b.pv.p[0], p.pid.surge.k_error * 0.6);
  EXPECT_GT(b.pv.i[0], 0.0);  // integrating from message times
  EXPECT_NEAR(b.pv.i[0], p.pid.surge.ki * 0.6 * 0.75, 1e-9);
}

TEST(VelocityPidNode, IntegratorFrozenWhileTheMixerReportsTheAxisReduced) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  p.arbiter.default_mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  VelocityPidNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  manual_velocity_cmd_t m{};
  m.velocity[0] = 1.0;
  m.valid = true;
  allocation_status_t a{};
  a.source = wrench_t::SOURCE_VELOCITY_PID;
  a.axis_reduced[0] = true;
  a.strategy = "test";
  for (TimeUs t = 0; t < 1'000'000; t += 50'000) {
    m.utime = a.utime = t;
    ex.inject(channels::kManualVelocity, m, t);
    ex.inject(channels::kAllocationStatus, a, t);
  }
  feed(ex, 0, 1'000'000);
  applied(ex, wrench_t::SOURCE_VELOCITY_PID, 0, 1'000'000);
  ex.run_until(900'000);
  EXPECT_TRUE(b.pv.integrator_frozen[0]);
  EXPECT_FALSE(b.pv.integrator_frozen[1]);  // sway: applied, not reduced
  EXPECT_DOUBLE_EQ(b.pv.i[0], 0.0);
}

TEST(VelocityPidNode, NanOdometryIsDroppedAndCounted) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  VelocityPidNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  feed(ex, 0, 200'000);
  auto bad = odom(200'000);
  bad.velocity[5] = NAN;
  ex.inject(channels::kOdometry, bad, 200'000);
  ex.run_until(300'000);
  EXPECT_EQ(node.counter_value("rejected.odometry.nan"), 1);
  EXPECT_EQ(node.rejected(), 1);
  for (double x : b.wv.tau) EXPECT_TRUE(std::isfinite(x));
}

// Runs the velocity PID in manual closed loop with odometry stopping at 1 s.
Bus run_until_stale(StaleAction action, TimeUs end) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  p.arbiter.default_mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  p.common.on_stale = action;
  p.common.odometry_timeout_s = 0.5;
  p.common.hold_s = 0.5;
  VelocityPidNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  manual_velocity_cmd_t m{};
  m.velocity[0] = 1.0;
  m.valid = true;
  for (TimeUs t = 0; t < end; t += 50'000) {
    m.utime = t;
    ex.inject(channels::kManualVelocity, m, t);
  }
  feed(ex, 0, 1'000'000);  // last odometry at 0.95 s
  ex.run_until(end);
  return b;
}

TEST(VelocityPidNode, OdometryThatStopsGivesNeutralWithinTheFreshnessLimit) {
  EXPECT_GT(run_until_stale(StaleAction::kNeutral, 1'450'000).wv.tau[0], 50.0);  // still fresh
  const auto b = run_until_stale(StaleAction::kNeutral, 1'500'000);  // 0.55 s after the last
  EXPECT_FALSE(b.wv.valid);  // nothing to give: the mixer's input lost (neutral, then disarm)
  EXPECT_EQ(b.wv.tau[0], 0.0);
  EXPECT_EQ(b.wv.tau[5], 0.0);
}

TEST(VelocityPidNode, OdometryThatStopsHoldsTheLastWrenchThenNeutral) {
  const auto held = run_until_stale(StaleAction::kHold, 1'900'000);  // stale, within hold_s
  EXPECT_GT(held.wv.tau[0], 50.0);
  const auto later = run_until_stale(StaleAction::kHold, 2'000'000);  // 1.05 s after: neutral
  EXPECT_EQ(later.wv.tau[0], 0.0);
}

TEST(StationKeepNode, ActsOnlyWhenArbitratedAndHoldsArrivalHeading) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  p.pid.weathervane = false;
  StationKeepNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  station_target_t st{};
  st.active = true;
  st.position[0] = 1.0;  // 1 m ahead
  st.heading_valid = false;
  arbitration_t arb{};
  arb.active_source = wrench_t::SOURCE_VELOCITY_PID;
  arb.reason = "test";
  for (TimeUs t = 0; t < 2'000'000; t += 50'000) {
    st.utime = arb.utime = t;
    if (t == 1'000'000) arb.active_source = wrench_t::SOURCE_STATION_KEEP;
    ex.inject(channels::kStationTarget, st, t);
    ex.inject(channels::kArbitration, arb, t);
    ex.inject(channels::kOdometry, odom(t, 0, 0, 0.3), t);
    const auto src = t < 1'000'000 ? wrench_t::SOURCE_VELOCITY_PID : wrench_t::SOURCE_STATION_KEEP;
    ex.inject(channels::kThrusterCommand, gate_cmd(t, thruster_command_t::GATE_ACTIVE, src), t);
  }
  ex.run_until(950'000);
  EXPECT_TRUE(b.ws.valid);
  EXPECT_FALSE(node.active());
  EXPECT_DOUBLE_EQ(node.terms().i[0], 0.0);  // no integration while standing by
  ex.run_until(1'950'000);
  EXPECT_TRUE(node.active());
  EXPECT_GT(node.terms().i[0], 0.0);
  EXPECT_NEAR(node.terms().setpoint[2], 0.3, 1e-12);  // the heading it arrived with
  EXPECT_NEAR(b.ws.tau[5], 0.0, 1e-9);
  auto bad = odom(1'960'000);
  bad.position[0] = INFINITY;
  ex.inject(channels::kOdometry, bad, 1'960'000);
  ex.run_until(2'000'000);
  EXPECT_EQ(node.counter_value("rejected.odometry.nan"), 1);
  // Odometry stopped at 1.95 s: neutral once older than the 0.5 s limit.
  ex.run_until(2'500'000);
  EXPECT_EQ(b.ws.tau[0], 0.0);
}

// Station keeping in control of a target 1 m ahead, odometry stopping at 1 s (last at 0.95 s).
Bus station_until_stale(StaleAction action, TimeUs end) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  p.common.on_stale = action;
  p.common.odometry_timeout_s = 0.5;
  p.common.hold_s = 0.5;
  StationKeepNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  station_target_t st{};
  st.active = true;
  st.position[0] = 1.0;
  st.heading_valid = true;
  arbitration_t arb{};
  arb.active_source = wrench_t::SOURCE_STATION_KEEP;
  arb.reason = "test";
  for (TimeUs t = 0; t < end; t += 50'000) {
    st.utime = arb.utime = t;
    ex.inject(channels::kStationTarget, st, t);
    ex.inject(channels::kArbitration, arb, t);
  }
  feed(ex, 0, 1'000'000);
  ex.run_until(end);
  b.stale = node.stale();
  return b;
}

TEST(StationKeepNode, OdometryThatStopsGivesNeutralWithinTheFreshnessLimit) {
  EXPECT_GT(station_until_stale(StaleAction::kNeutral, 1'450'000).ws.tau[0], 20.0);  // fresh
  const auto b = station_until_stale(StaleAction::kNeutral, 1'500'000);  // 0.55 s after the last
  EXPECT_FALSE(b.ws.valid);  // nothing to give: the mixer's input lost (neutral, then disarm)
  EXPECT_EQ(b.ws.tau[0], 0.0);
  EXPECT_EQ(b.ws.tau[5], 0.0);
}

TEST(StationKeepNode, OdometryThatStopsHoldsTheLastWrenchThenNeutral) {
  const auto fresh = station_until_stale(StaleAction::kHold, 1'000'000);
  const auto held = station_until_stale(StaleAction::kHold, 1'900'000);  // within hold_s
  EXPECT_GT(held.ws.tau[0], 20.0);
  EXPECT_EQ(held.ws.tau[0], fresh.ws.tau[0]);  // the last wrench computed from fresh odometry
  EXPECT_GE(held.stale, 1);                    // the stale odometry is counted
  const auto later = station_until_stale(StaleAction::kHold, 2'000'000);  // 1.05 s after: neutral
  EXPECT_FALSE(later.ws.valid);
  EXPECT_EQ(later.ws.tau[0], 0.0);
}

// A NaN in the other controller's wrench (used for the bumpless hand-over) is dropped and
// counted, in both nodes; the outputs stay finite.
TEST(ControllerNodes, NanWrenchFromTheOtherControllerIsDroppedAndCounted) {
  auto vp = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  auto sp = load_station_keep_node_params(config::Value::load_file(kOtter));
  VelocityPidNode v(vp);
  StationKeepNode s(sp);
  LockstepExecutor ex(0);
  ex.add(v);
  ex.add(s);
  Bus b;
  watch(ex, b);
  feed(ex, 0, 500'000);
  wrench_t w{};
  w.valid = true;
  w.tau[0] = NAN;
  w.source = wrench_t::SOURCE_STATION_KEEP;
  ex.inject(channels::kWrenchStation, w, 200'000);
  w.source = wrench_t::SOURCE_VELOCITY_PID;
  w.tau[0] = 1.0;
  w.tau[5] = INFINITY;
  ex.inject(channels::kWrenchVelocity, w, 250'000);
  ex.run_until(400'000);
  EXPECT_EQ(v.counter_value("rejected.wrench_station.nan"), 1);
  EXPECT_EQ(s.counter_value("rejected.wrench_velocity.nan"), 1);
  EXPECT_GE(v.rejected(), 1);
  EXPECT_GE(s.rejected(), 1);
  for (double x : b.wv.tau) EXPECT_TRUE(std::isfinite(x));
  for (double x : b.ws.tau) EXPECT_TRUE(std::isfinite(x));
}

// ---- Malformed input, table-driven. A reference run with good input on every channel; then,
// per case, the same run with one malformed message added at 0.525 s. The message must be
// counted (its counter and rejected() both 1) and never reach the controller: every message on
// the node's output channels is byte-identical to the reference run's.

constexpr TimeUs kBadAt = 525'000;
constexpr TimeUs kEnd = 1'500'000;
constexpr double kPi = 3.14159265358979323846;

using Inject = std::function<void(LockstepExecutor&)>;
struct BadCase {
  std::string what;
  Inject inject;
  std::string counter;
};

using Outputs = std::vector<std::pair<std::string, std::vector<std::uint8_t>>>;

void record(LockstepExecutor& ex, const std::set<std::string>& channels, Outputs& out) {
  ex.observe([&channels, &out](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (channels.count(ch)) out.emplace_back(ch, std::vector<std::uint8_t>(d, d + n));
  });
}

template <class Msg>
Inject bad(const std::string& channel, Msg m) {
  return [channel, m](LockstepExecutor& ex) { ex.inject(channel, m, kBadAt); };
}

// Odometry cases shared by both nodes: every bad odometry value of test/common/bad_values.hpp
// applied to this test's good message (odom(t, 0, 0, 0.1, 0.5)), counted under .nan or .range.
std::vector<BadCase> bad_odometry() {
  std::vector<BadCase> out;
  for (const auto& b : test::bad_values<odometry_t>()) {
    odometry_t m = odom(kBadAt, 0, 0, 0.1, 0.5);
    b.apply(m);
    out.push_back({std::string("odometry ") + b.what, bad(channels::kOdometry, m),
                   b.kind == test::BadKind::kNonFinite ? "rejected.odometry.nan"
                                                       : "rejected.odometry.range"});
  }
  return out;
}

allocation_status_t good_alloc(std::int8_t source) {
  allocation_status_t a{};
  a.source = source;
  a.scale = 1.0;
  a.n_thrusters = 2;
  a.names = {"port", "starboard"};
  a.saturated.assign(2, false);
  return a;
}

// Allocation status cases: each claims the node's axes reduced (so, if it were accepted, the
// integrators would freeze and the output would change).
std::vector<BadCase> bad_allocation(std::int8_t source) {
  auto a = [source](auto f) {
    allocation_status_t m = good_alloc(source);
    m.utime = kBadAt;
    m.axis_reduced[0] = m.axis_reduced[1] = m.axis_reduced[5] = true;
    f(m);
    return bad(channels::kAllocationStatus, m);
  };
  return {
      {"allocation scale 1.5", a([](allocation_status_t& m) { m.scale = 1.5; }),
       "rejected.allocation.invalid"},
      {"allocation achieved NaN", a([](allocation_status_t& m) { m.achieved[0] = NAN; }),
       "rejected.allocation.invalid"},
      {"allocation unknown source", a([](allocation_status_t& m) { m.source = 42; }),
       "rejected.allocation.invalid"},
  };
}

// Thruster command cases: each, if accepted, would stop the node's integrators (a disarmed or
// unknown gate), so the output would change.
std::vector<BadCase> bad_command(std::int8_t source) {
  auto c = [source](auto f) {
    thruster_command_t m = gate_cmd(kBadAt, thruster_command_t::GATE_DISARMED, source);
    m.n_thrusters = 2;
    m.names = {"port", "starboard"};
    m.command = {0.0, 0.0};
    f(m);
    return bad(channels::kThrusterCommand, m);
  };
  return {
      {"thruster command gate 9", c([](thruster_command_t& m) { m.gate = 9; }),
       "rejected.thruster_command.invalid"},
      {"thruster command 2.0", c([](thruster_command_t& m) { m.command[0] = 2.0; }),
       "rejected.thruster_command.invalid"},
      {"thruster command NaN", c([](thruster_command_t& m) { m.command[1] = NAN; }),
       "rejected.thruster_command.invalid"},
  };
}

template <class NodeT, class ParamsT>
Outputs run_with(const std::function<void(LockstepExecutor&)>& good, const Inject& extra,
                 const ParamsT& p, const std::set<std::string>& outs,
                 std::function<void(const NodeT&)> after = nullptr) {
  NodeT node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Outputs o;
  record(ex, outs, o);
  good(ex);
  if (extra) extra(ex);
  ex.run_until(kEnd);
  if (after) after(node);
  return o;
}

// Good input for the velocity PID in waypointing: a path in progress, an active NED setpoint
// with a heading, odometry, the mixer's status for the velocity PID, a station-keep wrench.
void velocity_good_input(LockstepExecutor& ex) {
  ex.inject(channels::kMode, mode(controller_mode_t::WAYPOINTING), 0);
  for (TimeUs t = 0; t < kEnd; t += 50'000) {
    ex.inject(channels::kOdometry, odom(t, 0, 0, 0.1, 0.5), t);
    velocity_setpoint_t sp{};
    sp.utime = t;
    sp.frame = velocity_setpoint_t::FRAME_NED;
    sp.active = true;
    sp.velocity[0] = 1.0;
    sp.velocity[1] = 0.2;
    sp.heading_valid = true;
    sp.target_heading = 0.5;
    ex.inject(channels::kVelocitySetpoint, sp, t);
    path_progress_t pr{};
    pr.utime = t;
    pr.path_id = 1;
    pr.segment = 0;
    pr.n_waypoints = 2;
    pr.distance_to_goal = 10.0;
    ex.inject(channels::kPathProgress, pr, t);
    auto a = good_alloc(wrench_t::SOURCE_VELOCITY_PID);
    a.utime = t;
    ex.inject(channels::kAllocationStatus, a, t);
    ex.inject(channels::kThrusterCommand,
              gate_cmd(t, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_VELOCITY_PID), t);
  }
}

TEST(VelocityPidNode, MalformedInputOfEachTypeIsDroppedCountedAndChangesNothing) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  const std::set<std::string> outs = {channels::kWrenchVelocity, channels::kArbitration,
                                      channels::kPidVelocity};
  const Outputs ref = run_with<VelocityPidNode>(velocity_good_input, nullptr, p, outs);
  // The reference is a live controller: velocity PID in charge, a finite, non-zero wrench.
  wrench_t last{};
  for (const auto& [ch, bytes] : ref)
    if (ch == channels::kWrenchVelocity)
      last.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
  ASSERT_TRUE(last.valid);
  ASSERT_GT(std::abs(last.tau[0]), 1.0);
  ASSERT_GT(std::abs(last.tau[5]), 1.0);

  std::vector<BadCase> cases = bad_odometry();
  for (auto& c : bad_allocation(wrench_t::SOURCE_VELOCITY_PID)) cases.push_back(c);
  for (auto& c : bad_command(wrench_t::SOURCE_VELOCITY_PID)) cases.push_back(c);
  auto sp = [](auto f) {
    velocity_setpoint_t m{};
    m.utime = kBadAt;
    m.frame = velocity_setpoint_t::FRAME_NED;
    m.active = true;
    m.velocity[0] = -1.0;
    m.heading_valid = true;
    m.target_heading = -1.0;
    f(m);
    return bad(channels::kVelocitySetpoint, m);
  };
  cases.push_back({"setpoint heading 4 rad",
                   sp([](velocity_setpoint_t& m) { m.target_heading = 4.0; }),
                   "rejected.setpoint.invalid"});
  cases.push_back({"setpoint heading -pi",
                   sp([](velocity_setpoint_t& m) { m.target_heading = -kPi; }),
                   "rejected.setpoint.invalid"});
  cases.push_back({"setpoint velocity NaN", sp([](velocity_setpoint_t& m) { m.velocity[1] = NAN; }),
                   "rejected.setpoint.invalid"});
  cases.push_back({"setpoint unknown frame", sp([](velocity_setpoint_t& m) { m.frame = 9; }),
                   "rejected.setpoint.invalid"});
  auto man = [](auto f) {
    manual_velocity_cmd_t m{};
    m.utime = kBadAt;
    m.valid = true;
    m.yaw_mode = manual_velocity_cmd_t::YAW_HEADING;
    f(m);
    return bad(channels::kManualVelocity, m);
  };
  cases.push_back({"manual heading 4 rad", man([](manual_velocity_cmd_t& m) { m.heading = 4.0; }),
                   "rejected.manual.invalid"});
  cases.push_back({"manual velocity NaN",
                   man([](manual_velocity_cmd_t& m) { m.velocity[0] = NAN; }),
                   "rejected.manual.invalid"});
  controller_mode_t bad_mode = mode(42);  // past DEPTH_HEADING_HOLD (9)
  bad_mode.is_translation = true;
  cases.push_back({"mode unknown", bad(channels::kMode, bad_mode), "rejected.mode.invalid"});
  path_progress_t pr{};
  pr.utime = kBadAt;
  pr.path_id = 1;
  pr.segment = 0;
  pr.complete = true;
  pr.distance_to_goal = NAN;
  cases.push_back(
      {"progress distance NaN", bad(channels::kPathProgress, pr), "rejected.progress.invalid"});
  pr.distance_to_goal = 0.0;
  pr.cross_track_error = INFINITY;
  cases.push_back(
      {"progress cross-track inf", bad(channels::kPathProgress, pr), "rejected.progress.invalid"});
  wrench_t w{};
  w.utime = kBadAt;
  w.source = wrench_t::SOURCE_STATION_KEEP;
  w.valid = true;
  w.tau[1] = NAN;
  cases.push_back(
      {"station wrench NaN", bad(channels::kWrenchStation, w), "rejected.wrench_station.nan"});

  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    std::int64_t counted = -1, rejected = -1;
    const Outputs got = run_with<VelocityPidNode>(velocity_good_input, c.inject, p, outs,
                                                  [&](const VelocityPidNode& n) {
                                                    counted = n.counter_value(c.counter);
                                                    rejected = n.rejected();
                                                  });
    EXPECT_EQ(counted, 1);
    EXPECT_EQ(rejected, 1);
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      ASSERT_EQ(got[i], ref[i]) << "output " << i << " on " << ref[i].first << " differs";
    }
  }
}

// Good input for station keeping in charge: an active target with a heading, the arbitration
// naming station keeping, odometry, the mixer's status for station keeping, a velocity wrench.
void station_good_input(LockstepExecutor& ex) {
  for (TimeUs t = 0; t < kEnd; t += 50'000) {
    ex.inject(channels::kOdometry, odom(t, 0, 0, 0.1, 0.5), t);
    station_target_t st{};
    st.utime = t;
    st.active = true;
    st.position[0] = 2.0;
    st.position[1] = 1.0;
    st.heading_valid = true;
    st.heading = 0.4;
    ex.inject(channels::kStationTarget, st, t);
    arbitration_t arb{};
    arb.utime = t;
    arb.mode = controller_mode_t::WAYPOINTING;
    arb.active_source = wrench_t::SOURCE_STATION_KEEP;
    arb.reason = "test";
    ex.inject(channels::kArbitration, arb, t);
    auto a = good_alloc(wrench_t::SOURCE_STATION_KEEP);
    a.utime = t;
    ex.inject(channels::kAllocationStatus, a, t);
    wrench_t w{};
    w.utime = t;
    w.source = wrench_t::SOURCE_VELOCITY_PID;
    w.valid = true;
    w.tau[0] = 30.0;
    ex.inject(channels::kWrenchVelocity, w, t);
    ex.inject(channels::kThrusterCommand,
              gate_cmd(t, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_STATION_KEEP), t);
  }
}

TEST(StationKeepNode, MalformedInputOfEachTypeIsDroppedCountedAndChangesNothing) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  const std::set<std::string> outs = {channels::kWrenchStation, channels::kPidStation};
  const Outputs ref = run_with<StationKeepNode>(station_good_input, nullptr, p, outs);
  wrench_t last{};
  for (const auto& [ch, bytes] : ref)
    if (ch == channels::kWrenchStation)
      last.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
  ASSERT_TRUE(last.valid);
  ASSERT_GT(std::abs(last.tau[0]), 1.0);
  ASSERT_GT(std::abs(last.tau[5]), 1.0);

  std::vector<BadCase> cases = bad_odometry();
  for (auto& c : bad_allocation(wrench_t::SOURCE_STATION_KEEP)) cases.push_back(c);
  for (auto& c : bad_command(wrench_t::SOURCE_STATION_KEEP)) cases.push_back(c);
  auto st = [](auto f) {
    station_target_t m{};
    m.utime = kBadAt;
    m.active = true;
    m.position[0] = -5.0;
    m.heading_valid = true;
    m.heading = -1.0;
    f(m);
    return bad(channels::kStationTarget, m);
  };
  cases.push_back({"target heading 4 rad", st([](station_target_t& m) { m.heading = 4.0; }),
                   "rejected.target.invalid"});
  cases.push_back({"target heading -pi", st([](station_target_t& m) { m.heading = -kPi; }),
                   "rejected.target.invalid"});
  cases.push_back({"target heading NaN (not valid)", st([](station_target_t& m) {
                     m.heading_valid = false;
                     m.heading = NAN;
                   }),
                   "rejected.target.invalid"});
  cases.push_back({"target position NaN", st([](station_target_t& m) { m.position[1] = NAN; }),
                   "rejected.target.invalid"});
  cases.push_back({"target position 2e6 m", st([](station_target_t& m) { m.position[0] = 2e6; }),
                   "rejected.target.invalid"});
  auto arb = [](auto f) {
    arbitration_t m{};
    m.utime = kBadAt;
    m.mode = controller_mode_t::WAYPOINTING;
    m.active_source = wrench_t::SOURCE_VELOCITY_PID;  // accepted, it would stand us down
    m.reason = "bad";
    f(m);
    return bad(channels::kArbitration, m);
  };
  cases.push_back({"arbitration unknown mode", arb([](arbitration_t& m) { m.mode = 42; }),
                   "rejected.arbitration.invalid"});
  cases.push_back({"arbitration unknown source",
                   arb([](arbitration_t& m) { m.active_source = 42; }),
                   "rejected.arbitration.invalid"});
  wrench_t w{};
  w.utime = kBadAt;
  w.source = wrench_t::SOURCE_VELOCITY_PID;
  w.valid = true;
  w.tau[0] = NAN;
  cases.push_back(
      {"velocity wrench NaN", bad(channels::kWrenchVelocity, w), "rejected.wrench_velocity.nan"});

  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    std::int64_t counted = -1, rejected = -1;
    const Outputs got = run_with<StationKeepNode>(station_good_input, c.inject, p, outs,
                                                  [&](const StationKeepNode& n) {
                                                    counted = n.counter_value(c.counter);
                                                    rejected = n.rejected();
                                                  });
    EXPECT_EQ(counted, 1);
    EXPECT_EQ(rejected, 1);
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      ASSERT_EQ(got[i], ref[i]) << "output " << i << " on " << ref[i].first << " differs";
    }
  }
}

}  // namespace
}  // namespace tiller::control

namespace tiller::control {
namespace {

// An ROV's estimate without a position source (tiller-nav, gnss.enabled false): attitude and
// depth valid, position and velocity not.
constexpr std::int32_t kRovValid = int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH};

// Station keeping on odometry valid until 1.0 s, then flagged without a position (tiller-nav:
// dead reckoning past its limit) until 3.0 s, then silent; the mixer's gate ACTIVE throughout.
// `wait_s`: odometry_invalid_neutral_s. Returns the station wrench at `at` and the status.
struct StationAt {
  wrench_t w;
  std::string status;
  std::int64_t invalid = 0, rejected = 0;
};
StationAt station_on_invalid_odometry(double wait_s, TimeUs at) {
  auto p = load_station_keep_node_params(config::Value::load_file(kOtter));
  p.common.invalid_neutral_s = wait_s;
  StationKeepNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  heartbeat_t hb{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == node.heartbeat_channel()) hb.decode(d, 0, n);
  });
  station_target_t st{};
  st.active = true;
  st.position[0] = 1.0;
  arbitration_t arb{};
  arb.active_source = wrench_t::SOURCE_STATION_KEEP;
  arb.reason = "test";
  for (TimeUs t = 0; t < 5'000'000; t += 50'000) {
    st.utime = arb.utime = t;
    ex.inject(channels::kStationTarget, st, t);
    ex.inject(channels::kArbitration, arb, t);
    odometry_t o = odom(t, 0, 0, 0.3);
    if (t >= 1'000'000) o.valid = kRovValid;
    if (t < 3'000'000) ex.inject(channels::kOdometry, o, t);
    ex.inject(channels::kThrusterCommand,
              gate_cmd(t, thruster_command_t::GATE_ACTIVE, wrench_t::SOURCE_STATION_KEEP), t);
  }
  ex.run_until(at);
  return {b.ws, hb.status, node.counter_value("odometry.invalid"), node.rejected()};
}

TEST(StationKeepNode, OdometryWithoutAValidPositionRefusesTheHoldWithAMessage) {
  auto r = station_on_invalid_odometry(60.0, 950'000);
  EXPECT_TRUE(r.w.valid);
  EXPECT_GT(r.w.tau[0], 0.0);
  // The last valid odometry at 0.95 s, 0.5 s limit (neutral config); the estimator keeps saying
  // "no position": a deliberate neutral, a valid zero wrench (the vehicle stays armed).
  r = station_on_invalid_odometry(60.0, 2'100'000);
  EXPECT_TRUE(r.w.valid);
  for (const double f : r.w.tau) EXPECT_EQ(f, 0.0);
  EXPECT_GE(r.invalid, 21);  // from 1.0 s at 20 Hz
  EXPECT_EQ(r.rejected, 0);  // well-formed: not a bad message
  EXPECT_EQ(r.status.rfind("position hold refused", 0), 0u) << r.status;
  EXPECT_NE(r.status.find("neutral, armed; resumes when it is valid"), std::string::npos)
      << r.status;
  // The estimator silent (last message 2.95 s, + 0.5 s): nothing is known, input lost.
  r = station_on_invalid_odometry(60.0, 3'600'000);
  EXPECT_FALSE(r.w.valid);
  EXPECT_EQ(r.status.rfind("position hold refused", 0), 0u) << r.status;
  // Past odometry_invalid_neutral_s since it went invalid (1.0 s + 0.8 s): input lost too.
  r = station_on_invalid_odometry(0.8, 1'750'000);
  EXPECT_TRUE(r.w.valid);
  r = station_on_invalid_odometry(0.8, 1'900'000);
  EXPECT_FALSE(r.w.valid);
  // 0: the invalid wrench at once (the mixer's INPUT_LOST and disarm), as before the wait.
  r = station_on_invalid_odometry(0.0, 2'100'000);
  EXPECT_FALSE(r.w.valid);
  EXPECT_EQ(r.w.tau[0], 0.0);
}

// The velocity PID in closed loop at 1 m/s asked: the odometry loses its velocity from 1.0 s to
// 2.0 s. A deliberate neutral (valid, zero) while the estimator says so; valid again, the PID
// resumes with its output ramped from zero over blend_s (1 s): no step.
TEST(VelocityPidNode, OdometryWithoutAValidVelocityGivesNeutral) {
  auto p = load_velocity_pid_node_params(config::Value::load_file(kOtter));
  VelocityPidNode node(p);
  LockstepExecutor ex(0);
  ex.add(node);
  Bus b;
  watch(ex, b);
  ex.inject(channels::kMode, mode(controller_mode_t::MANUAL_CLOSED_LOOP), 10'000);
  manual_velocity_cmd_t m{};
  m.velocity[0] = 1.0;
  m.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
  m.valid = true;
  for (TimeUs t = 10'000; t < 4'000'000; t += 50'000) {
    m.utime = t;
    ex.inject(channels::kManualVelocity, m, t);
    odometry_t o = odom(t, 0, 0, 0, 0.4);
    if (t >= 1'000'000 && t < 2'000'000) o.valid = kRovValid;
    ex.inject(channels::kOdometry, o, t);
  }
  applied(ex, wrench_t::SOURCE_VELOCITY_PID, 10'000, 4'000'000);
  ex.run_until(900'000);
  EXPECT_TRUE(b.wv.valid);
  const double before = b.wv.tau[0];
  EXPECT_GT(before, 0.0);
  ex.run_until(1'800'000);
  EXPECT_TRUE(b.wv.valid);
  EXPECT_EQ(b.wv.tau[0], 0.0);
  EXPECT_EQ(b.wv.tau[5], 0.0);
  EXPECT_GT(node.counter_value("odometry.invalid"), 10);
  ex.run_until(2'160'000);  // valid again from 2.0 s: at most a fifth of the way up
  EXPECT_TRUE(b.wv.valid);
  EXPECT_GT(b.wv.tau[0], 0.0);
  EXPECT_LT(b.wv.tau[0], 0.25 * before);
  ex.run_until(3'500'000);  // the blend done: the PID's own output again
  EXPECT_GT(b.wv.tau[0], 0.5 * before);
}

}  // namespace
}  // namespace tiller::control
