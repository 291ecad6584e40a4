// Round trip for every message type of the contract: encode -> decode -> encode gives the same
// bytes and the same field values, with every field set away from its default. Also checks the
// contract's shape rules: utime is the first field (LCM tools rely on it). The list of types
// comes from lcmtypes/*.lcm, so a new type without a round trip here fails the run. The sensor
// types are round-tripped in sensor_messages_test.cpp (same executable).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/esc_telemetry_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/joystick_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/sim_state_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/thruster_test_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/waypoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "round_trip.hpp"
#include "runtime/event.hpp"

namespace tiller {
namespace {
using test::round_trip;
using test::round_tripped;

// Every type in lcmtypes/: name -> the types it uses as fields.
std::map<std::string, std::set<std::string>> contract_types() {
  std::map<std::string, std::set<std::string>> out;
  const std::regex nested(R"(^\s*(\w+_t)\s+\w+(\[\w+\])?;)");
  for (const auto& e : std::filesystem::directory_iterator(TILLER_SOURCE_DIR "/lcmtypes")) {
    if (e.path().extension() != ".lcm") continue;
    auto& uses = out[e.path().stem().string()];
    std::ifstream in(e.path());
    std::string line;
    while (std::getline(in, line)) {
      std::smatch m;
      if (std::regex_search(line, m, nested)) uses.insert(m[1]);
    }
  }
  return out;
}

// After a full run: every contract type was round-tripped, directly or inside another type.
class EveryTypeCovered : public ::testing::Environment {
 public:
  void TearDown() override {
    if (::testing::GTEST_FLAG(filter) != "*") return;  // a partial run proves nothing here
    const auto types = contract_types();
    ASSERT_GT(types.size(), 15u);
    for (const auto& [name, uses] : types) {
      bool covered = round_tripped().count(name) != 0;
      for (const auto& [outer, outer_uses] : types)
        covered = covered || (outer_uses.count(name) && round_tripped().count(outer));
      EXPECT_TRUE(covered) << "lcmtypes/" << name << ".lcm has no round-trip test";
    }
  }
};
const auto* const kCovered = ::testing::AddGlobalTestEnvironment(new EveryTypeCovered);

TEST(Messages, JoystickState) {
  joystick_state_t m;
  m.utime = 123456789;
  m.device = "/dev/input/js0";
  m.connected = true;
  m.n_axes = 3;
  m.axes = {-32767, 0, 32767};
  m.n_buttons = 2;
  m.buttons = {true, false};
  const auto r = round_trip(m);
  EXPECT_EQ(r.utime, m.utime);
  EXPECT_EQ(r.device, m.device);
  EXPECT_EQ(r.axes, m.axes);
  EXPECT_EQ(r.buttons, m.buttons);
}

TEST(Messages, ManualDemandAndVelocity) {
  manual_demand_t d{};
  d.utime = 5;
  for (int i = 0; i < 6; ++i) d.demand[i] = -1.0 + 0.3 * i;
  d.valid = true;
  const auto r = round_trip(d);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(r.demand[i], d.demand[i]);
  EXPECT_TRUE(r.valid);

  manual_velocity_cmd_t v{};
  v.utime = 6;
  v.velocity[0] = 1.5;
  v.velocity[1] = -0.5;
  v.velocity[2] = 0.25;
  v.yaw_mode = manual_velocity_cmd_t::YAW_HEADING;
  v.yaw_rate = 0.1;
  v.heading = -3.0;
  v.yaw_torque = 12.5;
  v.valid = true;
  const auto rv = round_trip(v);
  EXPECT_EQ(rv.velocity[1], -0.5);
  EXPECT_EQ(rv.yaw_mode, manual_velocity_cmd_t::YAW_HEADING);
  EXPECT_EQ(rv.heading, -3.0);
  EXPECT_EQ(rv.yaw_torque, 12.5);
}

TEST(Messages, ModeArbitrationArm) {
  controller_mode_t m{};
  m.utime = 7;
  m.mode = controller_mode_t::WAYPOINTING;
  m.is_translation = true;
  m.source = "teleop";
  const auto r = round_trip(m);
  EXPECT_EQ(r.mode, controller_mode_t::WAYPOINTING);
  EXPECT_TRUE(r.is_translation);
  EXPECT_EQ(r.source, "teleop");

  arbitration_t a{};
  a.utime = 8;
  a.mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  a.active_source = wrench_t::SOURCE_STATION_KEEP;
  a.is_translation = true;
  a.reason = "within 2 m of goal";
  const auto ra = round_trip(a);
  EXPECT_EQ(ra.active_source, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_EQ(ra.reason, a.reason);

  arm_request_t q{};
  q.utime = 9;
  q.arm = true;
  q.source = "mission";
  EXPECT_EQ(round_trip(q).source, "mission");
  arm_state_t s{};
  s.utime = 10;
  s.armed = true;
  s.session = 3;
  s.reason = "armed by teleop";
  const auto rs = round_trip(s);
  EXPECT_TRUE(rs.armed);
  EXPECT_EQ(rs.session, 3);
  mission_command_t mc{};
  mc.utime = 11;
  mc.command_id = 1234567;
  mc.command = mission_command_t::PAUSE;
  mc.source = "tiller-mission";
  const auto rmc = round_trip(mc);
  EXPECT_EQ(rmc.command_id, 1234567);
  EXPECT_EQ(rmc.command, mission_command_t::PAUSE);
  EXPECT_EQ(rmc.source, "tiller-mission");
  EXPECT_EQ(rs.reason, s.reason);
}

TEST(Messages, PathWithNestedWaypoints) {
  path_t p{};
  p.utime = 11;
  p.path_id = 42;
  p.n_waypoints = 3;
  p.waypoints.resize(3);
  for (int i = 0; i < 3; ++i) {
    p.waypoints[i].position[0] = 10.0 * i;
    p.waypoints[i].position[1] = -5.0 * i;
    p.waypoints[i].position[2] = 0.5;
    p.waypoints[i].has_heading = (i == 2);
    p.waypoints[i].heading = 1.25 * i;
  }
  const auto r = round_trip(p);
  EXPECT_EQ(r.path_id, 42);
  ASSERT_EQ(r.waypoints.size(), 3u);
  EXPECT_EQ(r.waypoints[2].position[0], 20.0);
  EXPECT_EQ(r.waypoints[1].position[1], -5.0);
  EXPECT_TRUE(r.waypoints[2].has_heading);
  EXPECT_EQ(r.waypoints[2].heading, 2.5);
}

TEST(Messages, OdometryWithAndWithoutCovariance) {
  odometry_t o{};
  o.utime = 12;
  for (int i = 0; i < 3; ++i) {
    o.position[i] = 1.0 + i;
    o.orientation[i] = 0.1 * (i + 1);
  }
  for (int i = 0; i < 6; ++i) o.velocity[i] = -0.5 * i;
  o.n_pose_cov = 36;
  o.pose_covariance.assign(36, 0.0);
  o.pose_covariance[0] = 0.01;
  o.pose_covariance[35] = 0.02;
  o.n_velocity_cov = 0;
  const auto r = round_trip(o);
  EXPECT_EQ(r.position[2], 3.0);
  EXPECT_EQ(r.orientation[2], 0.30000000000000004);
  EXPECT_EQ(r.velocity[5], -2.5);
  ASSERT_EQ(r.pose_covariance.size(), 36u);
  EXPECT_EQ(r.pose_covariance[35], 0.02);
  EXPECT_TRUE(r.velocity_covariance.empty());
}

TEST(Messages, SetpointProgressStation) {
  velocity_setpoint_t v{};
  v.utime = 13;
  v.frame = velocity_setpoint_t::FRAME_NED;
  v.velocity[0] = 1.0;
  v.velocity[1] = 2.0;
  v.heading_valid = true;
  v.target_heading = 0.7;
  v.active = true;
  const auto rv = round_trip(v);
  EXPECT_EQ(rv.velocity[1], 2.0);
  EXPECT_EQ(rv.target_heading, 0.7);

  path_progress_t p{};
  p.utime = 14;
  p.path_id = 3;
  p.segment = 2;
  p.n_waypoints = 5;
  p.cross_track_error = -0.4;
  p.along_track_error = 7.5;
  p.distance_to_goal = 31.0;
  p.complete = true;
  p.skipped_waypoints = 1;
  const auto rp = round_trip(p);
  EXPECT_EQ(rp.cross_track_error, -0.4);
  EXPECT_EQ(rp.skipped_waypoints, 1);

  datum_t dm{};
  dm.utime = 17;
  dm.latitude = 59.437;
  dm.longitude = 10.6612;
  dm.altitude = 39.8;
  dm.source = datum_t::SOURCE_FIRST_FIX;
  const auto rdm = round_trip(dm);
  EXPECT_EQ(rdm.latitude, 59.437);
  EXPECT_EQ(rdm.longitude, 10.6612);
  EXPECT_EQ(rdm.source, datum_t::SOURCE_FIRST_FIX);

  path_speed_t ps{};
  ps.utime = 16;
  ps.path_id = 4;
  ps.n_segments = 3;
  ps.speed = {0.0, 1.0, 1.5};
  const auto rps = round_trip(ps);
  EXPECT_EQ(rps.path_id, 4);
  EXPECT_EQ(rps.speed, (std::vector<double>{0.0, 1.0, 1.5}));

  station_target_t s{};
  s.utime = 15;
  s.active = true;
  s.position[0] = 100.0;
  s.heading_valid = true;
  s.heading = -1.0;
  const auto rs = round_trip(s);
  EXPECT_EQ(rs.position[0], 100.0);
  EXPECT_EQ(rs.heading, -1.0);
}

TEST(Messages, WrenchPidAllocation) {
  wrench_t w{};
  w.utime = 16;
  w.source = wrench_t::SOURCE_VELOCITY_PID;
  for (int i = 0; i < 6; ++i) w.tau[i] = 10.0 * i - 25.0;
  w.valid = true;
  const auto rw = round_trip(w);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(rw.tau[i], w.tau[i]);

  pid_terms_t t{};
  t.utime = 17;
  t.controller = "velocity";
  for (int i = 0; i < 3; ++i) {
    t.setpoint[i] = 1.0 * i;
    t.measured[i] = 2.0 * i;
    t.p[i] = 3.0 * i;
    t.i[i] = 4.0 * i;
    t.d[i] = 5.0 * i;
    t.feed_forward[i] = 6.0 * i;
    t.output[i] = 7.0 * i;
    t.integrator_frozen[i] = (i == 1);
  }
  const auto rt = round_trip(t);
  EXPECT_EQ(rt.d[2], 10.0);
  EXPECT_TRUE(rt.integrator_frozen[1]);

  allocation_status_t a{};
  a.utime = 18;
  a.source = wrench_t::SOURCE_STATION_KEEP;
  a.strategy = "prioritised";
  for (int i = 0; i < 6; ++i) {
    a.demanded[i] = i;
    a.achieved[i] = 0.5 * i;
    a.unallocated[i] = 0.5 * i;
    a.axis_reduced[i] = i % 2;
    a.axis_unactuated[i] = i >= 2 && i <= 4;
  }
  a.scale = 0.5;
  a.n_thrusters = 2;
  a.names = {"port", "starboard"};
  a.saturated = {true, false};
  const auto ra = round_trip(a);
  EXPECT_EQ(ra.strategy, "prioritised");
  EXPECT_EQ(ra.names[1], "starboard");
  EXPECT_TRUE(ra.saturated[0]);
  EXPECT_TRUE(ra.axis_unactuated[3]);
  EXPECT_EQ(ra.scale, 0.5);
}

TEST(Messages, ThrusterCommandAndEsc) {
  thruster_command_t c{};
  c.utime = 19;
  c.armed = true;
  c.source = wrench_t::SOURCE_MANUAL_DEMAND;
  c.n_thrusters = 4;
  c.names = {"t1", "t2", "t3", "t4"};
  c.command = {-1.0, -0.25, 0.25, 1.0};
  const auto rc = round_trip(c);
  EXPECT_EQ(rc.command, c.command);
  EXPECT_EQ(rc.names, c.names);

  thruster_test_t tt{};
  tt.utime = 22;
  tt.test_id = 3;
  tt.active = true;
  tt.thruster = 2;
  tt.command = -0.1;
  tt.source = "cockpit";
  const auto rtt = round_trip(tt);
  EXPECT_EQ(rtt.test_id, 3);
  EXPECT_EQ(rtt.thruster, 2);
  EXPECT_EQ(rtt.command, -0.1);
  EXPECT_TRUE(rtt.active);
  EXPECT_EQ(rtt.source, "cockpit");

  esc_output_t o{};
  o.utime = 20;
  o.backend = "i2c_tgy";
  o.armed = true;
  o.unit = esc_output_t::UNIT_THROTTLE_INT16;
  o.n_channels = 2;
  o.names = {"t1", "t2"};
  o.channel = {0x29, 0x2a};
  o.value = {-32767, 32767};
  o.normalized = {-1.0, 1.0};
  const auto ro = round_trip(o);
  EXPECT_EQ(ro.value, o.value);
  EXPECT_EQ(ro.channel, o.channel);

  esc_telemetry_t t{};
  t.utime = 21;
  t.n_escs = 1;
  t.names = {"t1"};
  t.address = {0x29};
  t.sample_utime = {20};
  t.rpm = {1234.5};
  t.voltage = {15.9};
  t.current = {3.2};
  t.temperature = {31.0};
  t.alive = {true};
  const auto rt = round_trip(t);
  EXPECT_EQ(rt.rpm[0], 1234.5);
  EXPECT_TRUE(rt.alive[0]);

  esc_bus_status_t s{};
  s.utime = 22;
  s.backend = "pca9685";
  s.bus = "/dev/i2c-1";
  s.armed = false;
  s.command_timeout = true;
  s.cycles = 1000;
  s.timeouts = 2;
  s.n_escs = 2;
  s.names = {"a", "b"};
  s.present = {true, false};
  s.write_errors = {0, 17};
  s.read_errors = {1, 0};
  s.last_errno = {0, 6};
  const auto rs = round_trip(s);
  EXPECT_EQ(rs.write_errors[1], 17);
  EXPECT_EQ(rs.last_errno[1], 6);
  EXPECT_TRUE(rs.command_timeout);
}

TEST(Messages, HeartbeatAndSimState) {
  heartbeat_t h{};
  h.utime = 23;
  h.process = "mixer";
  h.state = heartbeat_t::STATE_DEGRADED;
  h.status = "odometry stale";
  h.received = 100;
  h.rejected = 3;
  h.stale = 1;
  h.published = 50;
  h.n_counters = 2;
  h.counter_names = {"rejected.wrench.nan", "malformed.TILLER_WRENCH_VELOCITY"};
  h.counter_values = {2, 1};
  const auto rh = round_trip(h);
  EXPECT_EQ(rh.counter_names, h.counter_names);
  EXPECT_EQ(rh.counter_values, h.counter_values);
  EXPECT_EQ(rh.state, heartbeat_t::STATE_DEGRADED);

  sim_state_t s{};
  s.utime = 24;
  for (int i = 0; i < 6; ++i) {
    s.eta[i] = i;
    s.nu[i] = -i;
    s.nu_r[i] = 0.5 * i;
  }
  s.current_ned[0] = 0.26;
  s.n_thrusters = 2;
  s.names = {"port", "stbd"};
  s.thrust = {119.7, -66.7};
  const auto rs = round_trip(s);
  EXPECT_EQ(rs.thrust[1], -66.7);
  EXPECT_EQ(rs.nu_r[4], 2.0);
}

// Contract shape: every .lcm struct starts with `int64_t utime;` and every field line carries a
// comment with its unit or range.
TEST(Messages, EveryTypeStartsWithUtimeAndDocumentsItsFields) {
  // Types only used inside others (waypoint_t) carry no utime of their own.
  const auto all = contract_types();
  std::set<std::string> nested;
  for (const auto& [name, uses] : all) nested.insert(uses.begin(), uses.end());
  ASSERT_GT(all.size(), 15u);
  const std::regex field(
      R"(^\s*(int8_t|int16_t|int32_t|int64_t|double|float|boolean|string|\w+_t)\s+\w+(\[\w+\])?;(.*)$)");
  for (const auto& [t, uses] : all) {
    std::ifstream in(std::string(TILLER_SOURCE_DIR) + "/lcmtypes/" + t + ".lcm");
    ASSERT_TRUE(in) << t;
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
      std::smatch m;
      if (!std::regex_match(line, m, field)) continue;
      if (first && !nested.count(t)) {
        EXPECT_TRUE(std::regex_search(line, std::regex(R"(^\s*int64_t\s+utime;)")))
            << t << ": first field is not utime";
      }
      first = false;
      EXPECT_NE(m[3].str().find("//"), std::string::npos)
          << t << ": field without a comment: " << line;
    }
    EXPECT_FALSE(first) << t << ": no fields found";
  }
}

}  // namespace
}  // namespace tiller
