// tiller-rov-control's waypointing (a mission on an ROV): refused without a valid position and
// taken on the mission's repeat once there is one, counted once; flown without the pilot's stick;
// the follower's NED velocity setpoint turned into the body frame for surge and sway; the depth
// reference moved at half the heave max_rate toward the path's depth interpolated along the
// segment, the heading reference at half the yaw max_rate toward the follower's heading; the
// station target held at the end. Hand-computed on the 6-thruster ROV (config/control/
// seed001_rov6.yaml: heave max_rate 0.4 m/s, yaw 0.8 rad/s, 50 Hz).
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include <cmath>
#include <string>

#include "control/rov_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::control {
namespace {

const std::string kRov6 = std::string(TILLER_SOURCE_DIR) + "/config/control/seed001_rov6.yaml";

struct Rig {
  Rig() : node(params()), ex(0) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kWrenchRov) wrench.decode(d, 0, n);
      if (ch == channels::kArbitration) arb.decode(d, 0, n);
    });
  }
  static RovControlParams params() {
    RovControlParams p = load_rov_control_file(kRov6);
    p.require_position_covariance = false;  // odometry_t.valid alone says whether it is valid
    return p;
  }
  // Gate and odometry at 20 Hz over [t0, t1): the vehicle at (north, 0), `depth`, heading `yaw`,
  // at rest; the follower's setpoint and progress on the path (0,0,2) -> (10,0,4); no stick.
  void feed(TimeUs t0, TimeUs t1, std::int32_t valid, double north, double depth, double yaw,
            bool station = false) {
    for (TimeUs t = t0; t < t1; t += 50'000) {
      thruster_command_t c{};
      c.utime = t;
      c.armed = true;
      c.gate = thruster_command_t::GATE_ACTIVE;
      c.source = wrench_t::SOURCE_ROV_CONTROL;
      ex.inject(channels::kThrusterCommand, c, t);
      odometry_t o{};
      o.utime = t;
      o.valid = valid;
      o.position[0] = north;
      o.position[2] = depth;
      o.orientation[2] = yaw;
      ex.inject(channels::kOdometry, o, t);
      velocity_setpoint_t s{};
      s.utime = t;
      s.frame = velocity_setpoint_t::FRAME_NED;
      s.velocity[0] = 0.3;  // north at 0.3 m/s
      s.heading_valid = true;
      s.target_heading = 0.5;
      s.active = !station;
      ex.inject(channels::kVelocitySetpoint, s, t);
      path_progress_t pr{};
      pr.utime = t;
      pr.path_id = 1;
      pr.segment = 0;
      pr.n_waypoints = 2;
      pr.complete = station;
      ex.inject(channels::kPathProgress, pr, t);
      station_target_t st{};
      st.utime = t;
      st.active = station;
      st.position[0] = 10;
      st.position[1] = 0.5;
      st.heading_valid = true;
      st.heading = 0.0;
      ex.inject(channels::kStationTarget, st, t);
    }
  }
  void path(TimeUs t) {
    path_t p{};
    p.utime = t;
    p.path_id = 1;
    p.n_waypoints = 2;
    p.waypoints.resize(2);
    p.waypoints[0].position[2] = 2.0;
    p.waypoints[1].position[0] = 10.0;
    p.waypoints[1].position[2] = 4.0;
    ex.inject(channels::kPath, p, t);
  }
  void request(TimeUs t) {
    controller_mode_t m{};
    m.utime = t;
    m.mode = controller_mode_t::WAYPOINTING;
    m.source = "mission";
    ex.inject(channels::kMode, m, t);
  }
  RovControlNode node;
  LockstepExecutor ex;
  wrench_t wrench{};
  arbitration_t arb{};
};

constexpr std::int32_t kAll = odometry_t::VALID_ALL;
constexpr std::int32_t kNoPosition = int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH};

TEST(RovWaypointing, RefusedWithoutAPositionThenTakenOnTheMissionsRepeatWithoutAStick) {
  Rig r;
  r.path(0);
  r.feed(0, 3'000'000, kNoPosition, 5.0, 2.0, 0.0);
  for (TimeUs t = 100'000; t < 3'000'000; t += 1'000'000) r.request(t);  // tiller-mission's 1 Hz
  r.ex.run_until(2'950'000);
  EXPECT_EQ(r.node.mode(), controller_mode_t::MANUAL_OPEN_LOOP);
  EXPECT_EQ(r.node.counter_value("mode.refused"), 1);  // three requests, counted once
  EXPECT_NE(std::string(r.arb.reason).find("waypointing refused"), std::string::npos)
      << r.arb.reason;
  r.feed(3'000'000, 5'000'000, kAll, 5.0, 2.0, 0.0);
  r.request(3'100'000);
  r.ex.run_until(4'950'000);
  EXPECT_EQ(r.node.mode(), controller_mode_t::WAYPOINTING);
  EXPECT_EQ(r.arb.mode, controller_mode_t::WAYPOINTING);  // the mixer's gate: autonomy, START
  EXPECT_EQ(r.arb.active_source, wrench_t::SOURCE_ROV_CONTROL);
  EXPECT_TRUE(r.wrench.valid);  // no TILLER_MANUAL_DEMAND at all
  EXPECT_EQ(r.node.counter_value("mode.refused"), 1);
}

TEST(RovWaypointing, SetpointInTheBodyFrameAndTheReferencesMoveTowardThePathAtHalfTheirRates) {
  Rig r;
  r.path(0);
  // Facing east (yaw pi/2): the setpoint north 0.3 m/s is body sway -0.3 (to port), surge 0.
  const double yaw = M_PI / 2;
  r.feed(0, 4'000'000, kAll, 5.0, 2.0, yaw);
  r.request(100'000);  // the references start at the vehicle: depth 2.0, heading pi/2
  r.ex.run_until(3'100'000);
  // Sway's rate setpoint has ramped at max_accel 0.5 m/s^2 to -0.3; surge's stays 0.
  EXPECT_NEAR(r.node.axes().setpoint(1), -0.3, 1e-9);
  EXPECT_NEAR(r.node.axes().setpoint(0), 0.0, 1e-9);
  // At north 5 on (0,0,2) -> (10,0,4) the path is at 3.0 m: the depth reference moves 0.2 m/s,
  // so it has 3.0 m after 5 s; after ~3 s from the start about 2.6 m.
  const double t_ref = 3.1 - 0.1;  // s in waypointing (one tick either way)
  EXPECT_NEAR(r.node.depth_reference(), 2.0 + 0.2 * t_ref, 0.2 * 0.02 + 1e-9);
  // The heading reference from pi/2 toward 0.5 at 0.4 rad/s: pi/2 - 1.2 = 0.371 would pass 0.5,
  // so it has stopped at 0.5 (1.07 rad in 2.68 s).
  EXPECT_NEAR(r.node.heading_reference(), 0.5, 1e-9);
  r.feed(4'000'000, 8'000'000, kAll, 5.0, 2.0, yaw);
  r.ex.run_until(7'900'000);
  EXPECT_NEAR(r.node.depth_reference(), 3.0, 1e-9);  // reached, and held there
  EXPECT_EQ(r.node.axes().target(2), r.node.depth_reference());
}

TEST(RovWaypointing, TheStationTargetIsHeldAtTheLastWaypointsDepth) {
  Rig r;
  r.path(0);
  r.feed(0, 1'000'000, kAll, 9.8, 4.0, 0.0);
  r.request(100'000);
  r.feed(1'000'000, 4'000'000, kAll, 9.8, 4.0, 0.0, /*station=*/true);
  // The station's reference starts at the vehicle (9.8, 0) and moves toward (10, 0.5), 0.539 m
  // away, at half the surge max_rate (0.25 m/s): 0.25 m along after 1 s.
  r.ex.run_until(2'000'000);
  EXPECT_EQ(r.node.axes().role(0), AxisRole::kHold);
  EXPECT_EQ(r.node.axes().role(1), AxisRole::kHold);
  const double moved = std::hypot(r.node.axes().target(0) - 9.8, r.node.axes().target(1) - 0.0);
  EXPECT_NEAR(moved, 0.25, 0.25 * 0.05 + 1e-9);  // within a tick or two of 1 s
  EXPECT_NEAR((r.node.axes().target(1) - 0.0) / (r.node.axes().target(0) - 9.8), 0.5 / 0.2, 1e-9);
  r.ex.run_until(3'900'000);  // 2.15 s: there, and held
  EXPECT_EQ(r.node.axes().target(0), 10.0);
  EXPECT_EQ(r.node.axes().target(1), 0.5);
  EXPECT_NEAR(r.node.depth_reference(), 4.0, 1e-9);  // the path complete: the last point's depth
  EXPECT_TRUE(r.node.axes().holding(0));
  // 0.2 m short of the target north: surge pushes forward (kp e, e = 0.2 m in the body frame).
  EXPECT_GT(r.wrench.tau[0], 0.0);
}

}  // namespace
}  // namespace tiller::control
