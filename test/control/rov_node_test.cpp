// tiller-rov-control's node and odometry_t.valid: an estimate without a valid depth (a pressure
// sensor lost) is not taken, so depth hold's wrench goes invalid (neutral through the mixer's
// gate) within the odometry freshness limit, counted in odometry.invalid, not as a bad message;
// position hold is refused while the estimate has no valid position (no GNSS, no DVL). The modes
// that do not use the depth (heading hold, stabilise, rate) fly without one: heading hold on the
// 4-thruster ROV, which has no heave, and on the 6-thruster one with its pressure sensor lost;
// one that uses it is refused while it is invalid.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/wrench_t.hpp>

#include <cstdint>
#include <string>

#include "control/rov_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::control {
namespace {

const std::string kRov6 = std::string(TILLER_SOURCE_DIR) + "/config/control/seed001_rov6.yaml";
const std::string kRov4 = std::string(TILLER_SOURCE_DIR) + "/config/control/seed000_rov4.yaml";

struct Rig {
  explicit Rig(const RovControlParams& p = load_rov_control_file(kRov6)) : node(p), ex(0) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kWrenchRov) wrench.decode(d, 0, n);
      if (ch == channels::kArbitration) arb.decode(d, 0, n);
      if (ch == channels::kMode) {
        controller_mode_t m;
        m.decode(d, 0, n);
        if (m.source == "rov-control") mode_out = m, ++modes_out;  // not the test's requests
      }
    });
  }
  // Pilot, gate and odometry at 20 Hz from t0 to t1; the vehicle at 2 m depth, 0.5 m above
  // the depth held once the odometry loses `valid` bits from `t_lost`.
  void feed(TimeUs t0, TimeUs t1, std::int32_t valid_before, std::int32_t valid_after,
            TimeUs t_lost) {
    for (TimeUs t = t0; t < t1; t += 50'000) {
      manual_demand_t m{};
      m.utime = t;
      m.valid = true;
      ex.inject(channels::kManualDemand, m, t);
      thruster_command_t c{};
      c.utime = t;
      c.armed = true;
      c.gate = thruster_command_t::GATE_ACTIVE;
      c.source = wrench_t::SOURCE_ROV_CONTROL;
      c.arm_allowed = true;
      ex.inject(channels::kThrusterCommand, c, t);
      odometry_t o{};
      o.utime = t;
      o.valid = t < t_lost ? valid_before : valid_after;
      o.position[2] = t < 500'000 ? 2.0 : 1.5;
      o.orientation[2] = t < 500'000 ? 0.0 : -0.2;  // turned 0.2 rad anticlockwise after 0.5 s
      ex.inject(channels::kOdometry, o, t);
    }
  }
  void request(std::int8_t mode, TimeUs t) {
    controller_mode_t m{};
    m.utime = t;
    m.mode = mode;
    m.source = "test";
    ex.inject(channels::kMode, m, t);
  }
  RovControlNode node;
  LockstepExecutor ex;
  wrench_t wrench{};
  arbitration_t arb{};
  controller_mode_t mode_out{};  // what the node itself published on TILLER_MODE
  int modes_out = 0;
};

constexpr std::int32_t kAll = odometry_t::VALID_ALL;
constexpr std::int32_t kNoDepth = int{odometry_t::VALID_ALL} & ~int{odometry_t::VALID_DEPTH};
constexpr std::int32_t kNoPosition = int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH};
constexpr std::int32_t kAttitudeOnly = odometry_t::VALID_ATTITUDE;

TEST(RovControlNode, DepthHoldGoesNeutralWhenTheDepthIsNoLongerValid) {
  Rig r;
  r.feed(0, 3'000'000, kAll, kNoDepth, 1'500'000);
  r.request(controller_mode_t::DEPTH_HOLD, 100'000);
  r.ex.run_until(1'450'000);
  ASSERT_EQ(r.arb.active_source, wrench_t::SOURCE_ROV_CONTROL) << r.arb.reason;
  EXPECT_TRUE(r.wrench.valid);
  EXPECT_GT(r.wrench.tau[2], 1.0);  // 0.5 m above the held 2.0 m: pushing down (FRD +Z), N
  r.ex.run_until(2'900'000);
  EXPECT_FALSE(r.wrench.valid);
  for (double tau : r.wrench.tau) EXPECT_EQ(tau, 0.0);
  EXPECT_GE(r.node.counter_value("odometry.invalid"), 28);  // 1.5 .. 2.9 s at 20 Hz
  EXPECT_EQ(r.node.rejected(), 0);                          // well-formed messages: not bad input
}

TEST(RovControlNode, PositionHoldRefusedWithoutAValidPosition) {
  RovControlParams p = load_rov_control_file(kRov6);
  p.require_position_covariance = false;  // so only odometry_t.valid can refuse it
  Rig r(p);
  r.feed(0, 1'000'000, kNoPosition, kNoPosition, 0);
  r.request(controller_mode_t::POSITION_HOLD, 200'000);
  r.ex.run_until(900'000);
  EXPECT_EQ(r.node.counter_value("mode.refused"), 1);
  EXPECT_NE(r.arb.mode, controller_mode_t::POSITION_HOLD);
  EXPECT_NE(std::string(r.arb.reason).find("still in"), std::string::npos) << r.arb.reason;
}

// Position hold whose position is lost (the DVL's bottom lock) falls back to depth and heading
// hold, says so, tells the pilot's station (TILLER_MODE), and does not come back with the
// position: only a new request brings it back.
TEST(RovControlNode, PositionHoldFallsBackOnLossAndDoesNotResumeSilently) {
  RovControlParams p = load_rov_control_file(kRov6);
  p.require_position_covariance = false;
  Rig r(p);
  r.feed(0, 2'000'000, kAll, kNoPosition, 1'000'000);
  r.feed(2'000'000, 4'000'000, kAll, kAll, 0);  // the position is back from 2 s
  r.request(controller_mode_t::POSITION_HOLD, 100'000);
  r.ex.run_until(950'000);
  ASSERT_EQ(r.arb.mode, controller_mode_t::POSITION_HOLD) << r.arb.reason;
  EXPECT_EQ(r.modes_out, 0);
  r.ex.run_until(1'100'000);
  EXPECT_EQ(r.arb.mode, controller_mode_t::DEPTH_HEADING_HOLD);
  EXPECT_NE(std::string(r.arb.reason).find("position lost"), std::string::npos) << r.arb.reason;
  EXPECT_NE(std::string(r.arb.reason).find("select position hold again"), std::string::npos);
  EXPECT_EQ(r.modes_out, 1);
  EXPECT_EQ(r.mode_out.mode, controller_mode_t::DEPTH_HEADING_HOLD);
  EXPECT_EQ(r.mode_out.source, "rov-control");
  EXPECT_EQ(r.node.counter_value("position_hold.lost"), 1);
  EXPECT_TRUE(r.wrench.valid);  // depth and heading still held
  EXPECT_TRUE(r.node.axes().holding(2));
  EXPECT_TRUE(r.node.axes().holding(5));
  EXPECT_FALSE(r.node.axes().holding(0));
  // The position is valid again from 2 s: still depth and heading hold.
  r.ex.run_until(2'900'000);
  EXPECT_EQ(r.arb.mode, controller_mode_t::DEPTH_HEADING_HOLD);
  // The teleop repeating the fallback it was told of changes nothing; a new request does.
  r.request(controller_mode_t::DEPTH_HEADING_HOLD, 2'950'000);
  r.request(controller_mode_t::POSITION_HOLD, 3'000'000);
  r.ex.run_until(3'500'000);
  EXPECT_EQ(r.arb.mode, controller_mode_t::POSITION_HOLD) << r.arb.reason;
  EXPECT_EQ(r.node.counter_value("position_hold.lost"), 1);
  // on_loss: manual hands the stick straight to the mixer.
  p.position_loss_mode = controller_mode_t::MANUAL_OPEN_LOOP;
  Rig m(p);
  m.feed(0, 2'000'000, kAll, kNoPosition, 1'000'000);
  m.request(controller_mode_t::POSITION_HOLD, 100'000);
  m.ex.run_until(1'900'000);
  EXPECT_EQ(m.arb.mode, controller_mode_t::MANUAL_OPEN_LOOP);
  EXPECT_EQ(m.mode_out.mode, controller_mode_t::MANUAL_OPEN_LOOP);
}

// Heading hold uses the attitude only: on an estimate without a depth it holds the heading (the
// old node took no such message and gave an invalid, neutral wrench).
TEST(RovControlNode, HeadingHoldFliesWithoutADepth) {
  for (const std::string& file : {kRov4, kRov6}) {
    Rig r(load_rov_control_file(file));
    r.feed(0, 2'000'000, kAttitudeOnly, kAttitudeOnly, 0);
    r.request(controller_mode_t::HEADING_HOLD, 100'000);
    r.ex.run_until(1'900'000);
    EXPECT_EQ(r.arb.mode, controller_mode_t::HEADING_HOLD) << file << ": " << r.arb.reason;
    EXPECT_EQ(r.arb.active_source, wrench_t::SOURCE_ROV_CONTROL) << file;
    EXPECT_TRUE(r.wrench.valid) << file;
    // Held at 0 (captured at rest before 0.5 s), now 0.2 rad anticlockwise: turning back, N m.
    EXPECT_TRUE(r.node.axes().holding(5)) << file;
    EXPECT_GT(r.wrench.tau[5], 1.0) << file;
    EXPECT_EQ(r.node.counter_value("odometry.invalid"), 0) << file;
  }
}

// Stabilise flies on the 6-thruster ROV without a depth; depth hold is refused while there is
// none, naming why, and the mode in force is kept.
TEST(RovControlNode, WithoutADepthStabiliseFliesAndDepthHoldIsRefused) {
  Rig r;
  r.feed(0, 2'000'000, kAttitudeOnly, kAttitudeOnly, 0);
  r.request(controller_mode_t::STABILISE, 100'000);
  r.ex.run_until(900'000);
  EXPECT_EQ(r.arb.mode, controller_mode_t::STABILISE) << r.arb.reason;
  EXPECT_TRUE(r.wrench.valid);
  r.request(controller_mode_t::DEPTH_HOLD, 1'000'000);
  r.ex.run_until(1'900'000);
  EXPECT_EQ(r.arb.mode, controller_mode_t::STABILISE);
  EXPECT_EQ(std::string(r.arb.reason),
            "depth hold refused: the odometry carries no valid depth; still in stabilise");
  EXPECT_EQ(r.node.counter_value("mode.refused"), 1);
  EXPECT_TRUE(r.wrench.valid);
}

}  // namespace
}  // namespace tiller::control
