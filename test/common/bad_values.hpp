// The one place for per-type test inputs: for every message type a node subscribes to, a good
// message (good<Msg>(channel, t, ctx): one that every node accepts on that channel at time t)
// and the ways to break its contract (bad_values<Msg>(): each mutation takes a good message
// outside what its .lcm file allows, either a non-finite number or a value out of range).
// input_checks_test sends every bad value to every (node, channel) pair the nodes declare;
// the controller tests use the same lists. A type whose contract has no value of one kind
// (no floating-point field: nothing non-finite; booleans and text only: nothing out of range)
// says so in missing_kinds<Msg>() with the reason, tied to the type's LCM hash so that a field
// added later fails the test until it has bad values.
#pragma once

#include <cctype>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/dvl_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/joystick_state_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/pressure_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/thruster_test_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "core/time.hpp"
#include "runtime/channels.hpp"
#include "runtime/event.hpp"

namespace tiller::test {

enum class BadKind { kNonFinite, kRange };

inline const char* kind_name(BadKind k) {
  return k == BadKind::kNonFinite ? "non-finite" : "out of range";
}

template <class Msg>
struct BadValue {
  const char* what;
  BadKind kind;
  void (*apply)(Msg&);
};

// A kind of bad value the type's contract cannot express, and why.
struct MissingKind {
  BadKind kind;
  const char* why;
};

// What a node expects beyond the contract (from its config): the thruster names, in order.
struct InputContext {
  std::vector<std::string> thrusters;
};

constexpr double kTestPi = 3.14159265358979323846;
constexpr double kHuge = 1e300;

// ---- good messages. Plausible, inside every range, slowly changing with t; one scenario
// across all channels: waypointing with station keeping in force, armed, a path in progress.
template <class Msg>
Msg good(const std::string& channel, TimeUs t, const InputContext& ctx);

template <>
inline odometry_t good(const std::string&, TimeUs t, const InputContext&) {
  odometry_t m{};
  m.utime = t;
  m.valid = odometry_t::VALID_ALL;
  m.position[0] = 0.5 * to_seconds(t);
  m.position[1] = 0.1;
  m.orientation[2] = 0.5;
  m.velocity[0] = 0.5;
  m.velocity[5] = 0.02;
  return m;
}

template <>
inline velocity_setpoint_t good(const std::string&, TimeUs t, const InputContext&) {
  velocity_setpoint_t m{};
  m.utime = t;
  m.frame = velocity_setpoint_t::FRAME_NED;
  m.velocity[0] = 1.0;
  m.velocity[1] = 0.2;
  m.heading_valid = true;
  m.target_heading = 0.5;
  m.active = true;
  return m;
}

template <>
inline station_target_t good(const std::string&, TimeUs t, const InputContext&) {
  station_target_t m{};
  m.utime = t;
  m.active = true;
  m.position[0] = 2.0;
  m.position[1] = 1.0;
  m.heading_valid = true;
  m.heading = 0.4;
  return m;
}

template <>
inline wrench_t good(const std::string& channel, TimeUs t, const InputContext&) {
  wrench_t m{};
  m.utime = t;
  m.source = channel == channels::kWrenchStation    ? wrench_t::SOURCE_STATION_KEEP
             : channel == channels::kWrenchRov      ? wrench_t::SOURCE_ROV_CONTROL
             : channel == channels::kWrenchFailsafe ? wrench_t::SOURCE_FAILSAFE
                                                    : wrench_t::SOURCE_VELOCITY_PID;
  // The scenario has no failsafe in force: tiller-failsafe's wrench says nothing (invalid).
  m.valid = channel != channels::kWrenchFailsafe;
  m.tau[0] = 30.0;
  m.tau[1] = 5.0;
  m.tau[5] = 3.0;
  return m;
}

template <>
inline allocation_status_t good(const std::string&, TimeUs t, const InputContext& ctx) {
  allocation_status_t m{};
  m.utime = t;
  m.source = wrench_t::SOURCE_STATION_KEEP;
  m.strategy = "direction_preserving";
  m.scale = 1.0;
  m.n_thrusters = static_cast<std::int32_t>(ctx.thrusters.size());
  m.names = ctx.thrusters;
  m.saturated.assign(ctx.thrusters.size(), false);
  return m;
}

template <>
inline arbitration_t good(const std::string&, TimeUs t, const InputContext&) {
  arbitration_t m{};
  m.utime = t;
  m.mode = controller_mode_t::WAYPOINTING;
  m.active_source = wrench_t::SOURCE_STATION_KEEP;
  m.reason = "test";
  return m;
}

template <>
inline manual_demand_t good(const std::string&, TimeUs t, const InputContext&) {
  manual_demand_t m{};
  m.utime = t;
  m.demand[0] = 0.2;
  m.demand[1] = 0.1;
  m.demand[5] = 0.1;
  m.valid = true;
  return m;
}

template <>
inline manual_velocity_cmd_t good(const std::string&, TimeUs t, const InputContext&) {
  manual_velocity_cmd_t m{};
  m.utime = t;
  m.velocity[0] = 0.5;
  m.yaw_mode = manual_velocity_cmd_t::YAW_HEADING;
  m.heading = 0.3;
  m.valid = true;
  return m;
}

template <>
inline controller_mode_t good(const std::string&, TimeUs t, const InputContext&) {
  controller_mode_t m{};
  m.utime = t;
  m.mode = controller_mode_t::WAYPOINTING;
  m.source = "test";
  return m;
}

template <>
inline arm_request_t good(const std::string&, TimeUs t, const InputContext&) {
  arm_request_t m{};
  m.utime = t;
  m.arm = true;
  m.source = "test";
  return m;
}

template <>
inline arm_state_t good(const std::string&, TimeUs t, const InputContext&) {
  arm_state_t m{};
  m.utime = t;
  m.armed = true;
  m.reason = "test";
  return m;
}

// A heartbeat on TILLER_HEARTBEAT_<NODE> names that node (tiller-launch's monitor checks).
template <>
inline heartbeat_t good(const std::string& channel, TimeUs t, const InputContext&) {
  heartbeat_t m{};
  m.utime = t;
  const std::string prefix = "TILLER_HEARTBEAT_";
  for (std::size_t i = channel.rfind(prefix, 0) == 0 ? prefix.size() : 0; i < channel.size(); ++i)
    m.process += channel[i] == '_' ? '-' : static_cast<char>(std::tolower(channel[i]));
  m.status = "ok";
  m.n_counters = 1;
  m.counter_names = {"ticks.run"};
  m.counter_values = {t / 1000};
  return m;
}

template <>
inline power_t good(const std::string&, TimeUs t, const InputContext&) {
  power_t m{};
  m.utime = t;
  m.voltage = 15.5;
  m.current = 8.0;
  m.power = 124.0;
  m.consumed_charge = 0.1;
  m.consumed_energy = 1.5;
  m.monitor = "sim";
  return m;
}

template <>
inline leak_t good(const std::string&, TimeUs t, const InputContext&) {
  leak_t m{};
  m.utime = t;
  m.n_probes = 2;
  m.names = {"main_tube", "battery_tube"};
  m.wet = {0, 0};
  m.readable = {1, 1};
  m.any_wet = false;
  return m;
}

template <>
inline vehicle_status_t good(const std::string&, TimeUs t, const InputContext&) {
  vehicle_status_t m{};
  m.utime = t;
  m.active = vehicle_status_t::EVENT_BATTERY_WARN;
  m.latched = 5;  // EVENT_BATTERY_WARN | EVENT_LEAK
  m.action = vehicle_status_t::ACTION_WARN;
  m.reason = "battery 14.0 V < warning 14.2 V";
  return m;
}

template <>
inline mission_command_t good(const std::string&, TimeUs t, const InputContext&) {
  mission_command_t m{};
  m.utime = t;
  m.command_id = 1;
  m.command = mission_command_t::START;
  m.source = "test";
  return m;
}

template <>
inline thruster_test_t good(const std::string&, TimeUs t, const InputContext&) {
  thruster_test_t m{};
  m.utime = t;
  m.test_id = 1;
  m.active = true;
  m.thruster = 0;
  m.command = 0.1;
  m.source = "test";
  return m;
}

template <>
inline pid_terms_t good(const std::string&, TimeUs t, const InputContext&) {
  pid_terms_t m{};
  m.utime = t;
  m.controller = "velocity";
  m.setpoint[0] = 1.0;
  m.measured[0] = 0.9;
  m.p[0] = 20.0;
  m.i[0] = 3.0;
  m.output[0] = 23.0;
  return m;
}

template <>
inline path_t good(const std::string&, TimeUs t, const InputContext&) {
  path_t m{};
  m.utime = t;
  m.path_id = 7;
  m.n_waypoints = 2;
  m.waypoints.resize(2);
  m.waypoints[1].position[0] = 20.0;
  m.waypoints[1].position[1] = 10.0;
  m.waypoints[1].has_heading = true;
  m.waypoints[1].heading = 1.0;
  return m;
}

template <>
inline path_progress_t good(const std::string&, TimeUs t, const InputContext&) {
  path_progress_t m{};
  m.utime = t;
  m.path_id = 7;
  m.segment = 0;
  m.n_waypoints = 2;
  m.distance_to_goal = 10.0;
  m.along_track_error = 10.0;
  return m;
}

template <>
inline path_speed_t good(const std::string&, TimeUs t, const InputContext&) {
  path_speed_t m{};
  m.utime = t;
  m.path_id = 7;
  m.n_segments = 2;
  m.speed = {1.0, 0.5};
  return m;
}

template <>
inline datum_t good(const std::string&, TimeUs t, const InputContext&) {
  datum_t m{};
  m.utime = t;
  m.latitude = 59.437;
  m.longitude = 10.6612;
  m.altitude = 39.8;
  m.source = datum_t::SOURCE_CONFIG;
  return m;
}

// Neutral for the first 0.2 s (so an ESC arms), then 0.3 on every thruster.
template <>
inline thruster_command_t good(const std::string&, TimeUs t, const InputContext& ctx) {
  thruster_command_t m{};
  m.utime = t;
  m.armed = true;
  m.source = wrench_t::SOURCE_STATION_KEEP;
  m.n_thrusters = static_cast<std::int32_t>(ctx.thrusters.size());
  m.names = ctx.thrusters;
  m.command.assign(ctx.thrusters.size(), t < 200'000 ? 0.0 : 0.3);
  return m;
}

template <>
inline esc_output_t good(const std::string&, TimeUs t, const InputContext& ctx) {
  esc_output_t m{};
  m.utime = t;
  m.backend = "sim";
  m.armed = true;
  m.unit = esc_output_t::UNIT_PULSE_US;
  const auto n = ctx.thrusters.size();
  m.n_channels = static_cast<std::int32_t>(n);
  m.names = ctx.thrusters;
  m.channel.resize(n);
  for (std::size_t i = 0; i < n; ++i) m.channel[i] = static_cast<std::int32_t>(i);
  m.value.assign(n, 1600);
  m.normalized.assign(n, 0.25);
  return m;
}

// Centred for the first 0.25 s (so the teleop sees the stick centred), then deflected.
template <>
inline joystick_state_t good(const std::string&, TimeUs t, const InputContext&) {
  joystick_state_t m{};
  m.utime = t;
  m.device = "test";
  m.connected = true;
  m.n_axes = 8;
  m.axes.assign(8, static_cast<std::int16_t>(t < 250'000 ? 0 : 6000));
  m.n_buttons = 12;
  m.buttons.assign(12, false);
  return m;
}

// Sensors (tiller-nav's inputs): one vehicle 2 m deep, heading 0.5 rad, going north at 0.5 m/s,
// level; fixes consistent with it (latitude 59.43 deg + 0.5 m/s north).
template <>
inline gnss_fix_t good(const std::string&, TimeUs t, const InputContext&) {
  gnss_fix_t m{};
  m.utime = t;
  m.gnss_utime = 1'780'000'000'000'000 + t;
  m.fix_type = gnss_fix_t::FIX_3D;
  m.satellites = 10;
  m.latitude = 59.43 + 0.5 * to_seconds(t) / 111'300.0;
  m.longitude = 10.47;
  m.altitude = 40.0;
  m.altitude_msl = 1.0;
  m.position_std[0] = m.position_std[1] = 1.5;
  m.position_std[2] = 3.0;
  m.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  m.hdop = 0.9;
  m.velocity_valid = true;
  m.speed = 0.5;
  m.course = 0.0;
  m.device = "test";
  return m;
}

template <>
inline imu_t good(const std::string&, TimeUs t, const InputContext&) {
  imu_t m{};
  m.utime = t;
  m.specific_force[2] = -9.81;
  m.orientation_valid = true;
  m.orientation[0] = std::cos(0.25);  // yaw 0.5 rad about down
  m.orientation[3] = std::sin(0.25);
  for (int i : {0, 4, 8}) {
    m.angular_rate_covariance[i] = 1e-4;
    m.specific_force_covariance[i] = 0.01;
    m.orientation_covariance[i] = 3e-4;
  }
  m.calibration_system = m.calibration_gyro = m.calibration_accel = m.calibration_mag = 3;
  m.temperature = 25.0;
  return m;
}

template <>
inline heading_t good(const std::string&, TimeUs t, const InputContext&) {
  heading_t m{};
  m.utime = t;
  m.heading = 0.5;
  m.variance = 1e-3;
  m.reference = heading_t::REFERENCE_TRUE;
  m.source = heading_t::SOURCE_AHRS;
  m.device = "test";
  return m;
}

template <>
inline dvl_t good(const std::string&, TimeUs t, const InputContext&) {
  dvl_t m{};
  m.utime = t;
  m.bottom_lock = true;
  m.velocity[0] = 0.2;
  m.velocity[1] = -0.05;
  m.velocity[2] = 0.01;
  for (int i = 0; i < 3; ++i) m.velocity_covariance[4 * i] = 1e-4;
  m.fom = 0.01;
  m.altitude = 3.0;
  m.beams_valid = 4;
  m.sensor = "test";
  return m;
}

template <>
inline pressure_t good(const std::string&, TimeUs t, const InputContext&) {
  pressure_t m{};
  m.utime = t;
  m.water_density = 1025.0;
  m.surface_pressure = 101325.0;
  m.depth = 2.0;
  m.pressure = m.surface_pressure + m.depth * m.water_density * 9.80665;
  m.temperature = 12.0;
  m.depth_variance = 1e-4;
  m.sensor = "test";
  return m;
}

// ---- bad values: each takes good<Msg>() outside its contract.
template <class Msg>
std::vector<BadValue<Msg>> bad_values();
template <class Msg>
std::vector<MissingKind> missing_kinds() {
  return {};
}
// The LCM hash (getHash()) of the type when its missing_kinds() were written: a changed type
// (a field added) no longer matches and input_checks_test asks for its bad values.
template <class Msg>
std::int64_t missing_kinds_hash() {
  return 0;
}

constexpr BadKind kNF = BadKind::kNonFinite;
constexpr BadKind kOR = BadKind::kRange;

template <>
inline std::vector<BadValue<odometry_t>> bad_values() {
  return {
      {"position NaN", kNF, [](odometry_t& m) { m.position[0] = NAN; }},
      {"velocity inf", kNF, [](odometry_t& m) { m.velocity[5] = INFINITY; }},
      {"yaw NaN", kNF, [](odometry_t& m) { m.orientation[2] = NAN; }},
      {"yaw 4 rad", kOR, [](odometry_t& m) { m.orientation[2] = 4.0; }},
      {"yaw -pi", kOR, [](odometry_t& m) { m.orientation[2] = -kTestPi; }},
      {"pitch 1.6 rad", kOR, [](odometry_t& m) { m.orientation[1] = 1.6; }},
      {"unknown validity bit 32", kOR, [](odometry_t& m) { m.valid |= 32; }},
      {"pose covariance of 9", kOR,
       [](odometry_t& m) {
         m.n_pose_cov = 9;
         m.pose_covariance.assign(9, 0.01);
       }},
      {"velocity covariance NaN", kNF,
       [](odometry_t& m) {
         m.n_velocity_cov = 36;
         m.velocity_covariance.assign(36, 0.0);
         m.velocity_covariance[7] = NAN;
       }},
  };
}

template <>
inline std::vector<BadValue<gnss_fix_t>> bad_values() {
  return {
      {"latitude NaN", kNF, [](gnss_fix_t& m) { m.latitude = NAN; }},
      {"latitude 91 deg", kOR, [](gnss_fix_t& m) { m.latitude = 91.0; }},
      {"longitude inf", kNF, [](gnss_fix_t& m) { m.longitude = INFINITY; }},
      {"course 4 rad", kOR, [](gnss_fix_t& m) { m.course = 4.0; }},
      {"speed -1 m/s", kOR, [](gnss_fix_t& m) { m.speed = -1.0; }},
      {"position std NaN", kNF, [](gnss_fix_t& m) { m.position_std[0] = NAN; }},
      {"position std -1", kOR, [](gnss_fix_t& m) { m.position_std[0] = -1; }},
      {"unknown fix type", kOR, [](gnss_fix_t& m) { m.fix_type = 9; }},
  };
}

template <>
inline std::vector<BadValue<imu_t>> bad_values() {
  return {
      {"angular rate NaN", kNF, [](imu_t& m) { m.angular_rate[2] = NAN; }},
      {"angular rate 50 rad/s", kOR, [](imu_t& m) { m.angular_rate[0] = 50.0; }},
      {"quaternion of norm 2", kOR, [](imu_t& m) { m.orientation[0] = 2.0; }},
      {"quaternion NaN", kNF, [](imu_t& m) { m.orientation[1] = NAN; }},
      {"specific force 500", kOR, [](imu_t& m) { m.specific_force[1] = 500.0; }},
      {"orientation covariance -1", kOR, [](imu_t& m) { m.orientation_covariance[0] = -1.0; }},
  };
}

template <>
inline std::vector<BadValue<heading_t>> bad_values() {
  return {
      {"heading NaN", kNF, [](heading_t& m) { m.heading = NAN; }},
      {"heading 4 rad", kOR, [](heading_t& m) { m.heading = 4.0; }},
      {"heading -pi", kOR, [](heading_t& m) { m.heading = -kTestPi; }},
      {"variance 11", kOR, [](heading_t& m) { m.variance = 11.0; }},
      {"unknown reference", kOR, [](heading_t& m) { m.reference = 5; }},
  };
}

template <>
inline std::vector<BadValue<dvl_t>> bad_values() {
  return {
      {"velocity NaN", kNF, [](dvl_t& m) { m.velocity[0] = NAN; }},
      {"velocity 25 m/s", kOR, [](dvl_t& m) { m.velocity[1] = 25.0; }},
      {"fom -1", kOR, [](dvl_t& m) { m.fom = -1.0; }},
      {"altitude -3", kOR, [](dvl_t& m) { m.altitude = -3.0; }},
      {"covariance negative", kOR, [](dvl_t& m) { m.velocity_covariance[4] = -1.0; }},
      {"velocity without lock", kOR, [](dvl_t& m) { m.bottom_lock = false; }},
  };
}

template <>
inline std::vector<BadValue<pressure_t>> bad_values() {
  return {
      {"depth NaN", kNF, [](pressure_t& m) { m.depth = NAN; }},
      {"pressure -1 Pa", kOR, [](pressure_t& m) { m.pressure = -1.0; }},
      {"depth not the pressure's", kOR, [](pressure_t& m) { m.depth += 0.5; }},
      {"density 1200", kOR, [](pressure_t& m) { m.water_density = 1200.0; }},
  };
}

template <>
inline std::vector<BadValue<velocity_setpoint_t>> bad_values() {
  return {
      {"heading 4 rad", kOR, [](velocity_setpoint_t& m) { m.target_heading = 4.0; }},
      {"heading -pi", kOR, [](velocity_setpoint_t& m) { m.target_heading = -kTestPi; }},
      {"velocity 11 m/s", kOR, [](velocity_setpoint_t& m) { m.velocity[0] = 11.0; }},
      {"unknown frame", kOR, [](velocity_setpoint_t& m) { m.frame = 9; }},
      {"velocity NaN", kNF, [](velocity_setpoint_t& m) { m.velocity[1] = NAN; }},
      {"heading NaN", kNF, [](velocity_setpoint_t& m) { m.target_heading = NAN; }},
  };
}

template <>
inline std::vector<BadValue<station_target_t>> bad_values() {
  return {
      {"heading 4 rad", kOR, [](station_target_t& m) { m.heading = 4.0; }},
      {"heading -pi", kOR, [](station_target_t& m) { m.heading = -kTestPi; }},
      {"position 2e6 m", kOR, [](station_target_t& m) { m.position[0] = 2e6; }},
      {"position NaN", kNF, [](station_target_t& m) { m.position[1] = NAN; }},
      {"heading NaN (not valid)", kNF,
       [](station_target_t& m) {
         m.heading_valid = false;
         m.heading = NAN;
       }},
  };
}

template <>
inline std::vector<BadValue<wrench_t>> bad_values() {
  return {
      {"tau 1e300", kOR, [](wrench_t& m) { m.tau[0] = kHuge; }},
      {"tau -2e5", kOR, [](wrench_t& m) { m.tau[5] = -2e5; }},
      {"unknown source", kOR, [](wrench_t& m) { m.source = 42; }},
      {"tau NaN", kNF, [](wrench_t& m) { m.tau[1] = NAN; }},
      {"tau inf", kNF, [](wrench_t& m) { m.tau[5] = INFINITY; }},
  };
}

// Each also claims the axes reduced, so that, accepted, it would change a controller's output.
template <>
inline std::vector<BadValue<allocation_status_t>> bad_values() {
  return {
      {"scale 1.5", kOR,
       [](allocation_status_t& m) {
         m.axis_reduced[0] = m.axis_reduced[1] = m.axis_reduced[5] = true;
         m.scale = 1.5;
       }},
      {"unknown source", kOR,
       [](allocation_status_t& m) {
         m.axis_reduced[0] = m.axis_reduced[1] = m.axis_reduced[5] = true;
         m.source = 42;
       }},
      {"achieved NaN", kNF,
       [](allocation_status_t& m) {
         m.axis_reduced[0] = m.axis_reduced[1] = m.axis_reduced[5] = true;
         m.achieved[0] = NAN;
       }},
  };
}

template <>
inline std::vector<BadValue<arbitration_t>> bad_values() {
  return {
      {"unknown mode", kOR, [](arbitration_t& m) { m.mode = 42; }},
      {"unknown source", kOR, [](arbitration_t& m) { m.active_source = 42; }},
  };
}
template <>
inline std::vector<MissingKind> missing_kinds<arbitration_t>() {
  return {{kNF, "integers, a boolean and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<arbitration_t>() {
  return static_cast<std::int64_t>(0xc31ebe1501fb5fd6ULL);
}

template <>
inline std::vector<BadValue<manual_demand_t>> bad_values() {
  return {
      {"demand 1.5", kOR, [](manual_demand_t& m) { m.demand[0] = 1.5; }},
      {"demand -1e300", kOR, [](manual_demand_t& m) { m.demand[5] = -kHuge; }},
      {"demand NaN", kNF, [](manual_demand_t& m) { m.demand[1] = NAN; }},
  };
}

template <>
inline std::vector<BadValue<manual_velocity_cmd_t>> bad_values() {
  return {
      {"heading 4 rad", kOR, [](manual_velocity_cmd_t& m) { m.heading = 4.0; }},
      {"yaw rate 1e300", kOR, [](manual_velocity_cmd_t& m) { m.yaw_rate = kHuge; }},
      {"velocity 11 m/s", kOR, [](manual_velocity_cmd_t& m) { m.velocity[0] = 11.0; }},
      {"unknown yaw mode", kOR, [](manual_velocity_cmd_t& m) { m.yaw_mode = 5; }},
      {"velocity NaN", kNF, [](manual_velocity_cmd_t& m) { m.velocity[0] = NAN; }},
      {"yaw torque inf", kNF, [](manual_velocity_cmd_t& m) { m.yaw_torque = INFINITY; }},
  };
}

template <>
inline std::vector<BadValue<controller_mode_t>> bad_values() {
  return {
      {"unknown mode", kOR,
       [](controller_mode_t& m) {
         m.mode = 42;  // 0..8 are known (the ROV modes are 3..8)
         m.is_translation = true;
       }},
  };
}
template <>
inline std::vector<MissingKind> missing_kinds<controller_mode_t>() {
  return {{kNF, "integers, a boolean and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<controller_mode_t>() {
  return static_cast<std::int64_t>(0x6506a2a75906ca38ULL);
}

template <>
inline std::vector<BadValue<arm_request_t>> bad_values() {
  return {};
}
template <>
inline std::vector<MissingKind> missing_kinds<arm_request_t>() {
  return {{kNF, "a time, a boolean and text only"},
          {kOR, "a time, a boolean and text only: every decoded value is allowed"}};
}
template <>
inline std::int64_t missing_kinds_hash<arm_request_t>() {
  return static_cast<std::int64_t>(0xa799c353be403233ULL);
}

template <>
inline std::vector<BadValue<arm_state_t>> bad_values() {
  return {{"session -1", kOR, [](arm_state_t& m) { m.session = -1; }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<arm_state_t>() {
  return {{kNF, "a time, a boolean, an integer and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<arm_state_t>() {
  return static_cast<std::int64_t>(0x71e3eae676919edeULL);
}

template <>
inline std::vector<BadValue<heartbeat_t>> bad_values() {
  return {{"counter -1", kOR, [](heartbeat_t& m) { m.counter_values[0] = -1; }},
          {"65 counters", kOR, [](heartbeat_t& m) {
             m.n_counters = 65;
             m.counter_names.assign(65, "x");
             m.counter_values.assign(65, 0);
           }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<heartbeat_t>() {
  return {{kNF, "integers and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<heartbeat_t>() {
  return static_cast<std::int64_t>(0x17e12207035524d5ULL);
}

template <>
inline std::vector<BadValue<power_t>> bad_values() {
  return {{"voltage NaN", kNF, [](power_t& m) { m.voltage = std::nan(""); }},
          {"voltage 150", kOR, [](power_t& m) { m.voltage = 150; }},
          {"current 1e300", kOR, [](power_t& m) { m.current = kHuge; }}};
}
template <>
inline std::vector<BadValue<leak_t>> bad_values() {
  return {{"n_probes 33", kOR,
           [](leak_t& m) {
             m.n_probes = 33;
             m.names.assign(33, "p");
             m.wet.assign(33, 0);
             m.readable.assign(33, 1);
           }},
          {"unreadable dry", kOR, [](leak_t& m) { m.readable[1] = 0; }},
          {"any_wet inconsistent", kOR, [](leak_t& m) { m.any_wet = true; }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<leak_t>() {
  return {{kNF, "booleans, integers and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<leak_t>() {
  return static_cast<std::int64_t>(0x6192d0a14cf3160cULL);
}

template <>
inline std::vector<BadValue<vehicle_status_t>> bad_values() {
  return {{"action 8", kOR, [](vehicle_status_t& m) { m.action = 8; }},
          {"unknown event bit", kOR, [](vehicle_status_t& m) { m.active = 64; }},
          {"active not latched", kOR,
           [](vehicle_status_t& m) { m.active = vehicle_status_t::EVENT_GEOFENCE; }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<vehicle_status_t>() {
  return {{kNF, "integers and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<vehicle_status_t>() {
  return static_cast<std::int64_t>(0x71188dd317ad2972ULL);
}

template <>
inline std::vector<BadValue<mission_command_t>> bad_values() {
  return {{"command id 0", kOR, [](mission_command_t& m) { m.command_id = 0; }},
          {"unknown command 9", kOR, [](mission_command_t& m) { m.command = 9; }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<mission_command_t>() {
  return {{kNF, "integers and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<mission_command_t>() {
  return static_cast<std::int64_t>(0x70837850d67618afULL);
}

template <>
inline std::vector<BadValue<path_t>> bad_values() {
  return {
      {"waypoint heading 4 rad", kOR,
       [](path_t& m) {
         m.waypoints[1].has_heading = true;
         m.waypoints[1].heading = 4.0;
       }},
      {"waypoint heading 1e300", kOR,
       [](path_t& m) {
         m.waypoints[1].has_heading = true;
         m.waypoints[1].heading = kHuge;
       }},
      {"waypoint heading -pi", kOR,
       [](path_t& m) {
         m.waypoints[1].has_heading = true;
         m.waypoints[1].heading = -kTestPi;
       }},
      {"waypoint position 2e6 m", kOR, [](path_t& m) { m.waypoints[0].position[1] = 2e6; }},
      {"waypoint heading NaN", kNF,
       [](path_t& m) {
         m.waypoints[1].has_heading = true;
         m.waypoints[1].heading = NAN;
       }},
      {"waypoint position NaN", kNF, [](path_t& m) { m.waypoints[1].position[0] = NAN; }},
  };
}

template <>
inline std::vector<BadValue<path_progress_t>> bad_values() {
  return {
      {"segment -2", kOR, [](path_progress_t& m) { m.segment = -2; }},
      {"distance to goal -1 m", kOR, [](path_progress_t& m) { m.distance_to_goal = -1.0; }},
      {"distance to goal NaN", kNF,
       [](path_progress_t& m) {
         m.complete = true;
         m.distance_to_goal = NAN;
       }},
      {"cross-track inf", kNF, [](path_progress_t& m) { m.cross_track_error = INFINITY; }},
  };
}

template <>
inline std::vector<BadValue<datum_t>> bad_values() {
  return {
      {"latitude 91", kOR, [](datum_t& m) { m.latitude = 91.0; }},
      {"longitude -181", kOR, [](datum_t& m) { m.longitude = -181.0; }},
      {"latitude NaN", kNF, [](datum_t& m) { m.latitude = NAN; }},
      {"altitude inf", kNF, [](datum_t& m) { m.altitude = INFINITY; }},
      {"source 7", kOR, [](datum_t& m) { m.source = 7; }},
  };
}

template <>
inline std::vector<BadValue<path_speed_t>> bad_values() {
  return {
      {"speed -1 m/s", kOR, [](path_speed_t& m) { m.speed[1] = -1.0; }},
      {"speed 21 m/s", kOR, [](path_speed_t& m) { m.speed[0] = 21.0; }},
      {"speed NaN", kNF, [](path_speed_t& m) { m.speed[0] = NAN; }},
      {"speed inf", kNF, [](path_speed_t& m) { m.speed[1] = INFINITY; }},
  };
}

template <>
inline std::vector<BadValue<thruster_command_t>> bad_values() {
  return {
      {"command 1.5", kOR, [](thruster_command_t& m) { m.command.back() = 1.5; }},
      {"command -1e300", kOR, [](thruster_command_t& m) { m.command.front() = -kHuge; }},
      {"unknown source", kOR, [](thruster_command_t& m) { m.source = 42; }},
      {"command NaN", kNF, [](thruster_command_t& m) { m.command.front() = NAN; }},
  };
}

template <>
inline std::vector<BadValue<thruster_test_t>> bad_values() {
  return {
      {"test id 0", kOR, [](thruster_test_t& m) { m.test_id = 0; }},
      {"thruster 16", kOR, [](thruster_test_t& m) { m.thruster = 16; }},
      {"thruster -1", kOR, [](thruster_test_t& m) { m.thruster = -1; }},
      {"command 1.5", kOR, [](thruster_test_t& m) { m.command = 1.5; }},
      {"command NaN", kNF, [](thruster_test_t& m) { m.command = NAN; }},
  };
}

template <>
inline std::vector<BadValue<pid_terms_t>> bad_values() {
  return {{"p NaN", kNF, [](pid_terms_t& m) { m.p[0] = NAN; }},
          {"output inf", kNF, [](pid_terms_t& m) { m.output[2] = INFINITY; }},
          {"measured NaN", kNF, [](pid_terms_t& m) { m.measured[1] = NAN; }}};
}
template <>
inline std::vector<MissingKind> missing_kinds<pid_terms_t>() {
  return {{kOR, "its contract gives units, no range: any finite term is good"}};
}
template <>
inline std::int64_t missing_kinds_hash<pid_terms_t>() {
  return static_cast<std::int64_t>(0xd0445f225875c017ULL);
}

template <>
inline std::vector<BadValue<esc_output_t>> bad_values() {
  return {
      {"pulse 3000 us", kOR, [](esc_output_t& m) { m.value.front() = 3000; }},
      {"normalized 1.5", kOR, [](esc_output_t& m) { m.normalized.back() = 1.5; }},
      {"unknown unit", kOR, [](esc_output_t& m) { m.unit = 7; }},
      {"normalized NaN", kNF, [](esc_output_t& m) { m.normalized.front() = NAN; }},
  };
}

template <>
inline std::vector<BadValue<joystick_state_t>> bad_values() {
  return {
      {"axis -32768", kOR, [](joystick_state_t& m) { m.axes[1] = -32768; }},
      {"65 axes", kOR,
       [](joystick_state_t& m) {
         m.n_axes = 65;
         m.axes.assign(65, 0);
       }},
  };
}
template <>
inline std::vector<MissingKind> missing_kinds<joystick_state_t>() {
  return {{kNF, "integers, booleans and text only"}};
}
template <>
inline std::int64_t missing_kinds_hash<joystick_state_t>() {
  return static_cast<std::int64_t>(0x79273b6d6e394fa1ULL);
}

// ---- the same, by LCM type name, as encoded events (for tests that only know a channel's type).
using MakeEvent = std::function<Event(const std::string& channel, TimeUs t, const InputContext&)>;
struct TypeInputs {
  std::string type;  // LCM type name, as Node::subscribed_type() gives it
  std::int64_t hash = 0;
  MakeEvent good;
  struct Bad {
    std::string what;
    BadKind kind;
    MakeEvent make;
  };
  std::vector<Bad> bad;
  std::vector<MissingKind> missing;
  std::int64_t missing_hash = 0;
};

template <class Msg>
TypeInputs type_inputs() {
  TypeInputs ti;
  ti.type = Msg::getTypeName();
  ti.hash = Msg::getHash();
  ti.good = [](const std::string& ch, TimeUs t, const InputContext& ctx) {
    return encode(ch, t, good<Msg>(ch, t, ctx));
  };
  for (const auto& b : bad_values<Msg>()) {
    auto apply = b.apply;
    ti.bad.push_back(
        {b.what, b.kind, [apply](const std::string& ch, TimeUs t, const InputContext& ctx) {
           Msg m = good<Msg>(ch, t, ctx);
           apply(m);
           return encode(ch, t, m);
         }});
  }
  ti.missing = missing_kinds<Msg>();
  ti.missing_hash = missing_kinds_hash<Msg>();
  return ti;
}

// Every type with inputs here; a subscribed type missing from this list fails input_checks_test.
inline std::vector<TypeInputs> all_type_inputs() {
  return {type_inputs<odometry_t>(),
          type_inputs<velocity_setpoint_t>(),
          type_inputs<station_target_t>(),
          type_inputs<wrench_t>(),
          type_inputs<allocation_status_t>(),
          type_inputs<arbitration_t>(),
          type_inputs<manual_demand_t>(),
          type_inputs<manual_velocity_cmd_t>(),
          type_inputs<controller_mode_t>(),
          type_inputs<arm_request_t>(),
          type_inputs<arm_state_t>(),
          type_inputs<mission_command_t>(),
          type_inputs<path_t>(),
          type_inputs<path_progress_t>(),
          type_inputs<path_speed_t>(),
          type_inputs<datum_t>(),
          type_inputs<thruster_command_t>(),
          type_inputs<thruster_test_t>(),
          type_inputs<pid_terms_t>(),
          type_inputs<esc_output_t>(),
          type_inputs<joystick_state_t>(),
          type_inputs<heartbeat_t>(),
          type_inputs<vehicle_status_t>(),
          type_inputs<gnss_fix_t>(),
          type_inputs<imu_t>(),
          type_inputs<heading_t>(),
          type_inputs<pressure_t>(),
          type_inputs<power_t>(),
          type_inputs<leak_t>(),
          type_inputs<dvl_t>()};
}

}  // namespace tiller::test
