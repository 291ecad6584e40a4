// The velocity-PID node (with the arbiter) and the station-keep node: arbitration on the bus,
// integrators reset on entry and frozen by the mixer's status, NaN odometry dropped and
// counted, odometry that stops -> neutral or hold by config within the freshness limit (both
// nodes), a NaN wrench from the other controller dropped and counted.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/pid_terms_t.hpp>

#include <cmath>

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
  ex.run_until(900'000);
  EXPECT_TRUE(b.pv.integrator_frozen[0]);
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
  EXPECT_TRUE(b.wv.valid);
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
  EXPECT_TRUE(b.ws.valid);
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
  EXPECT_TRUE(later.ws.valid);
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

}  // namespace
}  // namespace tiller::control
