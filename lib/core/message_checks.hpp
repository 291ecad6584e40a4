// Message checks: one function per Tiller input type that says whether a decoded message may
// act, using the ranges written in its .lcm file (the contract). check(msg) returns nullptr
// when the message is good, else a short static reason ("yaw.range", "tau.range", ...) that a
// node counts before dropping the message (runtime/node.hpp reject()). No allocation, no
// throw. NaN and infinity fail every numeric check; headings must be in (-pi, pi] (so -pi is
// refused: the contract's representation of "south" is +pi).
// Covariances are checked over their count (n_pose_cov, n_velocity_cov), not the vector's size:
// lcm-gen's decode resizes an array of doubles only when its count is non-zero, so a node's
// reused decode target keeps the previous message's entries after one with no covariance.
//
// Usage in a handler (one counter per input, or one per reason):
//   if (checks::check(m) != nullptr) {
//     reject(*rejected_odometry_);
//     return;
//   }
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

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

namespace tiller::checks {

using Reason = const char*;  // nullptr: the message is good

namespace detail {
constexpr double kPi = 3.14159265358979323846;
inline bool finite(const double* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
inline bool within(const double* v, std::size_t n, double lo, double hi) {
  for (std::size_t i = 0; i < n; ++i)
    if (!(std::isfinite(v[i]) && v[i] >= lo && v[i] <= hi)) return false;
  return true;
}
// The first n entries of a variable-length array (its count field); false if it holds fewer.
template <class V>
bool finite_prefix(const V& v, std::int32_t n) {
  return n >= 0 && v.size() >= static_cast<std::size_t>(n) &&
         finite(v.data(), static_cast<std::size_t>(n));
}
// A heading or a wrapped angle: (-pi, pi].
inline bool heading(double a) {
  return std::isfinite(a) && a > -kPi && a <= kPi;
}
inline bool source(std::int8_t s) {
  return s >= wrench_t::SOURCE_NONE && s <= wrench_t::SOURCE_FAILSAFE;
}
inline bool mode(std::int8_t m) {
  return m >= controller_mode_t::MANUAL_OPEN_LOOP && m <= controller_mode_t::DEPTH_HEADING_HOLD;
}
// A 3x3 row-major covariance: finite, diagonal >= 0 (all zero: unknown).
inline bool covariance3(const double (&c)[9]) {
  return finite(c, 9) && c[0] >= 0 && c[4] >= 0 && c[8] >= 0;
}
// The first n entries of a variable-length array of booleans exist.
template <class V>
bool has(const V& v, std::int32_t n) {
  return n >= 0 && v.size() >= static_cast<std::size_t>(n);
}
}  // namespace detail

// odometry_t: known validity bits only (0..31); position and velocity finite; roll and yaw in
// (-pi, pi], pitch in [-pi/2, pi/2] (ZYX Euler); covariances 0 or 36 finite entries.
inline Reason check(const odometry_t& m) {
  using namespace detail;
  if (m.valid < 0 || m.valid > 31) return "valid.unknown";
  if (!finite(m.position, 3)) return "position.nan";
  if (!finite(m.orientation, 3)) return "orientation.nan";
  if (!heading(m.orientation[0])) return "roll.range";
  if (!(m.orientation[1] >= -kPi / 2 && m.orientation[1] <= kPi / 2)) return "pitch.range";
  if (!heading(m.orientation[2])) return "yaw.range";
  if (!finite(m.velocity, 6)) return "velocity.nan";
  if (m.n_pose_cov != 0 && m.n_pose_cov != 36) return "pose_cov.size";
  if (m.pose_covariance.size() < static_cast<std::size_t>(m.n_pose_cov)) return "pose_cov.size";
  if (!finite_prefix(m.pose_covariance, m.n_pose_cov)) return "pose_cov.nan";
  if (m.n_velocity_cov != 0 && m.n_velocity_cov != 36) return "velocity_cov.size";
  if (m.velocity_covariance.size() < static_cast<std::size_t>(m.n_velocity_cov))
    return "velocity_cov.size";
  if (!finite_prefix(m.velocity_covariance, m.n_velocity_cov)) return "velocity_cov.nan";
  return nullptr;
}

// velocity_setpoint_t: a known frame, each velocity in [-10, 10] m/s, the target heading
// finite and, when heading_valid, in (-pi, pi].
inline Reason check(const velocity_setpoint_t& m) {
  using namespace detail;
  if (m.frame != velocity_setpoint_t::FRAME_NED && m.frame != velocity_setpoint_t::FRAME_BODY)
    return "frame.unknown";
  if (!within(m.velocity, 3, -10, 10)) return "velocity.range";
  if (!std::isfinite(m.target_heading)) return "heading.nan";
  if (m.heading_valid && !heading(m.target_heading)) return "heading.range";
  return nullptr;
}

// station_target_t: position finite; heading finite and, when heading_valid, in (-pi, pi].
inline Reason check(const station_target_t& m) {
  using namespace detail;
  if (!finite(m.position, 3)) return "position.nan";
  if (!std::isfinite(m.heading)) return "heading.nan";
  if (m.heading_valid && !heading(m.heading)) return "heading.range";
  return nullptr;
}

// wrench_t: a known source, each component within +-1e5 (N, N m).
inline Reason check(const wrench_t& m) {
  using namespace detail;
  if (!source(m.source)) return "source.unknown";
  if (!within(m.tau, 6, -1e5, 1e5)) return "tau.range";
  return nullptr;
}

// allocation_status_t: a known source; demanded / achieved / unallocated finite; scale in
// [0, 1]; 0..16 thrusters.
inline Reason check(const allocation_status_t& m) {
  using namespace detail;
  if (!source(m.source)) return "source.unknown";
  if (!finite(m.demanded, 6)) return "demanded.nan";
  if (!finite(m.achieved, 6)) return "achieved.nan";
  if (!finite(m.unallocated, 6)) return "unallocated.nan";
  if (!(m.scale >= 0.0 && m.scale <= 1.0)) return "scale.range";
  if (m.n_thrusters < 0 || m.n_thrusters > 16) return "n_thrusters.range";
  return nullptr;
}

// arbitration_t: a known mode and a known source.
inline Reason check(const arbitration_t& m) {
  if (!detail::mode(m.mode)) return "mode.unknown";
  if (!detail::source(m.active_source)) return "source.unknown";
  return nullptr;
}

// manual_demand_t: each axis in [-1, 1].
inline Reason check(const manual_demand_t& m) {
  if (!detail::within(m.demand, 6, -1, 1)) return "demand.range";
  return nullptr;
}

// manual_velocity_cmd_t: velocity in [-10, 10] m/s, a known yaw mode, yaw rate in [-5, 5]
// rad/s, heading in (-pi, pi], yaw torque in [-1e4, 1e4] N m.
inline Reason check(const manual_velocity_cmd_t& m) {
  using namespace detail;
  if (!within(m.velocity, 3, -10, 10)) return "velocity.range";
  if (m.yaw_mode < manual_velocity_cmd_t::YAW_RATE ||
      m.yaw_mode > manual_velocity_cmd_t::YAW_TORQUE)
    return "yaw_mode.unknown";
  if (!within(&m.yaw_rate, 1, -5, 5)) return "yaw_rate.range";
  if (!heading(m.heading)) return "heading.range";
  if (!within(&m.yaw_torque, 1, -1e4, 1e4)) return "yaw_torque.range";
  return nullptr;
}

// controller_mode_t: a known mode.
inline Reason check(const controller_mode_t& m) {
  return detail::mode(m.mode) ? nullptr : "mode.unknown";
}

// arm_request_t: booleans and text only; always good once decoded. arm_state_t: session >= 0.
inline Reason check(const arm_request_t&) {
  return nullptr;
}
inline Reason check(const arm_state_t& m) {
  return m.session >= 0 ? nullptr : "session.range";
}

// mission_command_t: an id >= 1 and a known command.
inline Reason check(const mission_command_t& m) {
  if (m.command_id < 1) return "command_id.range";
  if (m.command < mission_command_t::START || m.command > mission_command_t::RELEASE)
    return "command.unknown";
  return nullptr;
}

// path_t: 0..10000 waypoints, each position within +-1e6 m, heading in (-pi, pi] where
// has_heading (ignored otherwise).
inline Reason check(const path_t& m) {
  using namespace detail;
  if (m.n_waypoints < 0 || m.n_waypoints > 10000) return "n_waypoints.range";
  for (const auto& w : m.waypoints) {
    if (!within(w.position, 3, -1e6, 1e6)) return "waypoint.position.range";
    if (w.has_heading && !heading(w.heading)) return "waypoint.heading.range";
  }
  return nullptr;
}

// path_speed_t: 0..10000 segments, each speed finite in [0, 20] m/s.
inline Reason check(const path_speed_t& m) {
  if (m.n_segments < 0 || m.n_segments > 10000 ||
      static_cast<std::size_t>(m.n_segments) != m.speed.size())
    return "n_segments.range";
  for (const double v : m.speed)
    if (!(v >= 0.0 && v <= 20.0)) return "speed.range";
  return nullptr;
}

// datum_t: latitude in [-90, 90], longitude in [-180, 180] deg, altitude within +-1e5 m, a known
// source.
inline Reason check(const datum_t& m) {
  if (!(m.latitude >= -90.0 && m.latitude <= 90.0)) return "latitude.range";
  if (!(m.longitude >= -180.0 && m.longitude <= 180.0)) return "longitude.range";
  if (!(m.altitude >= -1e5 && m.altitude <= 1e5)) return "altitude.range";
  if (m.source != datum_t::SOURCE_CONFIG && m.source != datum_t::SOURCE_FIRST_FIX)
    return "source.range";
  return nullptr;
}

// path_progress_t: segment >= -1, n_waypoints >= 0, errors finite, distance to goal >= 0.
inline Reason check(const path_progress_t& m) {
  if (m.segment < -1) return "segment.range";
  if (m.n_waypoints < 0) return "n_waypoints.range";
  if (!std::isfinite(m.cross_track_error) || !std::isfinite(m.along_track_error))
    return "error.nan";
  if (!(m.distance_to_goal >= 0.0) || !std::isfinite(m.distance_to_goal)) return "distance.range";
  return nullptr;
}

// thruster_command_t: a known source, 0..16 thrusters, each command in [-1, 1]. Only the first
// n_thrusters entries: lcm-gen's decode leaves a reused message's array as it was when the count
// is 0, so entries past the count are an earlier message's.
inline Reason check(const thruster_command_t& m) {
  if (!detail::source(m.source)) return "source.unknown";
  if (m.n_thrusters < 0 || m.n_thrusters > 16) return "n_thrusters.range";
  if (m.command.size() < static_cast<std::size_t>(m.n_thrusters) ||
      !detail::within(m.command.data(), static_cast<std::size_t>(m.n_thrusters), -1, 1))
    return "command.range";
  if (m.gate < thruster_command_t::GATE_DISARMED || m.gate > thruster_command_t::GATE_TEST)
    return "gate.unknown";
  return nullptr;
}

// thruster_test_t: an id >= 1, a thruster index 0..15, the command in [-1, 1] (the mixer holds
// it to its smaller thruster_test.max_command and the vehicle's thruster count).
inline Reason check(const thruster_test_t& m) {
  if (m.test_id < 1) return "test_id.range";
  if (m.thruster < 0 || m.thruster > 15) return "thruster.range";
  if (!(std::fabs(m.command) <= 1.0)) return "command.range";
  return nullptr;
}

// pid_terms_t: every term finite (its contract gives units, no range).
inline Reason check(const pid_terms_t& m) {
  using detail::finite;
  if (!finite(m.setpoint, 3) || !finite(m.measured, 3) || !finite(m.p, 3) || !finite(m.i, 3) ||
      !finite(m.d, 3) || !finite(m.feed_forward, 3) || !finite(m.output, 3))
    return "term.nan";
  return nullptr;
}

// esc_output_t: a known unit, 0..16 channels, values in the unit's range (int16 throttle
// -32767..32767, pulse 500..2500 us), normalized in [-1, 1].
inline Reason check(const esc_output_t& m) {
  if (m.unit != esc_output_t::UNIT_THROTTLE_INT16 && m.unit != esc_output_t::UNIT_PULSE_US)
    return "unit.unknown";
  if (m.n_channels < 0 || m.n_channels > 16) return "n_channels.range";
  const std::int32_t lo = m.unit == esc_output_t::UNIT_PULSE_US ? 500 : -32767;
  const std::int32_t hi = m.unit == esc_output_t::UNIT_PULSE_US ? 2500 : 32767;
  for (std::int32_t v : m.value)
    if (v < lo || v > hi) return "value.range";
  if (!detail::within(m.normalized.data(), m.normalized.size(), -1, 1)) return "normalized.range";
  return nullptr;
}

// joystick_state_t: 0..64 axes, each -32767..32767; 0..128 buttons.
inline Reason check(const joystick_state_t& m) {
  if (m.n_axes < 0 || m.n_axes > 64) return "n_axes.range";
  for (std::int16_t a : m.axes)
    if (a < -32767) return "axis.range";
  if (m.n_buttons < 0 || m.n_buttons > 128) return "n_buttons.range";
  return nullptr;
}

// heartbeat_t: 0..64 counters, each >= 0. Only the first n_counters values count: lcm-gen's
// decoder leaves a reused message's arrays as they were when a packet has 0 counters.
inline Reason check(const heartbeat_t& m) {
  if (m.n_counters < 0 || m.n_counters > 64) return "n_counters.range";
  const auto n = std::min(static_cast<std::size_t>(m.n_counters), m.counter_values.size());
  for (std::size_t i = 0; i < n; ++i)
    if (m.counter_values[i] < 0) return "counter.range";
  return nullptr;
}

// ---- sensors (issue 14): every range is the one in the type's .lcm comment.

// gnss_fix_t: times >= 0; a known fix type and accuracy source; satellites -1..255; latitude
// [-90, 90], longitude [-180, 180] deg; altitudes [-1e4, 1e5] m; position_std [0, 1e5] m; hdop
// [0, 100]; speed [0, 300] m/s; course in (-pi, pi]. Checked whatever the fix type (a driver
// fills a no-fix message with zeros, never NaN).
inline Reason check(const gnss_fix_t& m) {
  using namespace detail;
  if (m.utime < 0 || m.gnss_utime < 0) return "utime.range";
  if (m.fix_type < gnss_fix_t::FIX_NONE || m.fix_type > gnss_fix_t::FIX_DEAD_RECKONING)
    return "fix_type.unknown";
  if (m.satellites < -1 || m.satellites > 255) return "satellites.range";
  if (!within(&m.latitude, 1, -90, 90)) return "latitude.range";
  if (!within(&m.longitude, 1, -180, 180)) return "longitude.range";
  if (!within(&m.altitude, 1, -1e4, 1e5) || !within(&m.altitude_msl, 1, -1e4, 1e5))
    return "altitude.range";
  if (!within(m.position_std, 3, 0, 1e5)) return "position_std.range";
  if (m.accuracy_source < gnss_fix_t::ACCURACY_NONE ||
      m.accuracy_source > gnss_fix_t::ACCURACY_RECEIVER)
    return "accuracy_source.unknown";
  if (!within(&m.hdop, 1, 0, 100)) return "hdop.range";
  if (!within(&m.speed, 1, 0, 300)) return "speed.range";
  if (!heading(m.course)) return "course.range";
  return nullptr;
}

// imu_t: utime >= 0; rates within +-40 rad/s, specific force within +-400 m/s^2; orientation
// finite and, when valid, of norm in [0.99, 1.01]; covariances finite with diagonals >= 0;
// calibration levels -1..3; temperature [-60, 150] degC.
inline Reason check(const imu_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (!within(m.angular_rate, 3, -40, 40)) return "angular_rate.range";
  if (!within(m.specific_force, 3, -400, 400)) return "specific_force.range";
  if (!finite(m.orientation, 4)) return "orientation.nan";
  if (m.orientation_valid) {
    const double n2 = m.orientation[0] * m.orientation[0] + m.orientation[1] * m.orientation[1] +
                      m.orientation[2] * m.orientation[2] + m.orientation[3] * m.orientation[3];
    if (!(n2 >= 0.99 * 0.99 && n2 <= 1.01 * 1.01)) return "orientation.norm";
  }
  if (!covariance3(m.angular_rate_covariance)) return "angular_rate_cov.range";
  if (!covariance3(m.specific_force_covariance)) return "specific_force_cov.range";
  if (!covariance3(m.orientation_covariance)) return "orientation_cov.range";
  for (std::int8_t c :
       {m.calibration_system, m.calibration_gyro, m.calibration_accel, m.calibration_mag})
    if (c < -1 || c > 3) return "calibration.range";
  if (!within(&m.temperature, 1, -60, 150)) return "temperature.range";
  return nullptr;
}

// heading_t: utime >= 0; heading in (-pi, pi]; variance [0, 10] rad^2; known reference and
// source.
inline Reason check(const heading_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (!heading(m.heading)) return "heading.range";
  if (!within(&m.variance, 1, 0, 10)) return "variance.range";
  if (m.reference != heading_t::REFERENCE_MAGNETIC && m.reference != heading_t::REFERENCE_TRUE)
    return "reference.unknown";
  if (m.source < heading_t::SOURCE_MAGNETOMETER || m.source > heading_t::SOURCE_SIM)
    return "source.unknown";
  return nullptr;
}

// pressure_t: utime >= 0; pressure [0, 2e7] Pa; temperature [-40, 125] degC; depth [-1e3, 2e3]
// m; density [900, 1100] kg/m^3; surface pressure [5e4, 1.2e5] Pa; depth variance [0, 1e4] m^2;
// and depth is what the contract's formula gives from the others (within 1 mm).
inline Reason check(const pressure_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (!within(&m.pressure, 1, 0, 2e7)) return "pressure.range";
  if (!within(&m.temperature, 1, -40, 125)) return "temperature.range";
  if (!within(&m.water_density, 1, 900, 1100)) return "water_density.range";
  if (!within(&m.surface_pressure, 1, 5e4, 1.2e5)) return "surface_pressure.range";
  if (!within(&m.depth_variance, 1, 0, 1e4)) return "depth_variance.range";
  if (!within(&m.depth, 1, -1e3, 2e3)) return "depth.range";
  const double d = (m.pressure - m.surface_pressure) / (m.water_density * 9.80665);
  if (std::fabs(d - m.depth) > 1e-3) return "depth.inconsistent";
  return nullptr;
}

// dvl_t: utime >= 0; velocity [-20, 20] m/s each; covariance finite, its diagonal [0, 100]
// (m/s)^2 and symmetric; fom [0, 100] m/s; altitude [0, 1e3] m or -1 (none); without bottom lock
// the velocity is 0 and the altitude -1; beams_valid -1..4.
inline Reason check(const dvl_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (!within(m.velocity, 3, -20, 20)) return "velocity.range";
  if (!finite(m.velocity_covariance, 9)) return "velocity_covariance.range";
  for (int i = 0; i < 3; ++i) {
    const double d = m.velocity_covariance[4 * i];
    if (!(d >= 0 && d <= 100)) return "velocity_covariance.range";
    for (int j = 0; j < i; ++j)
      if (std::fabs(m.velocity_covariance[3 * i + j] - m.velocity_covariance[3 * j + i]) > 1e-9)
        return "velocity_covariance.asymmetric";
  }
  if (!within(&m.fom, 1, 0, 100)) return "fom.range";
  if (!(m.altitude == -1 || within(&m.altitude, 1, 0, 1e3))) return "altitude.range";
  if (m.beams_valid < -1 || m.beams_valid > 4) return "beams_valid.range";
  if (!m.bottom_lock && (m.velocity[0] != 0 || m.velocity[1] != 0 || m.velocity[2] != 0))
    return "velocity.unlocked";
  return nullptr;
}

// power_t: utime >= 0; voltage [0, 100] V; current [-1000, 1000] A; power [-1e5, 1e5] W;
// consumed charge [-1e4, 1e4] Ah; consumed energy [-1e6, 1e6] Wh.
inline Reason check(const power_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (!within(&m.voltage, 1, 0, 100)) return "voltage.range";
  if (!within(&m.current, 1, -1000, 1000)) return "current.range";
  if (!within(&m.power, 1, -1e5, 1e5)) return "power.range";
  if (!within(&m.consumed_charge, 1, -1e4, 1e4)) return "consumed_charge.range";
  if (!within(&m.consumed_energy, 1, -1e6, 1e6)) return "consumed_energy.range";
  return nullptr;
}

// leak_t: utime >= 0; 0..32 probes with names, wet and readable for each; an unreadable probe
// reads wet (fail safe); any_wet is the OR of wet.
inline Reason check(const leak_t& m) {
  using namespace detail;
  if (m.utime < 0) return "utime.range";
  if (m.n_probes < 0 || m.n_probes > 32) return "n_probes.range";
  if (!has(m.names, m.n_probes) || !has(m.wet, m.n_probes) || !has(m.readable, m.n_probes))
    return "probes.size";
  bool any = false;
  for (std::int32_t i = 0; i < m.n_probes; ++i) {
    if (!m.readable[i] && !m.wet[i]) return "wet.unreadable";
    any = any || m.wet[i];
  }
  if (any != m.any_wet) return "any_wet.inconsistent";
  return nullptr;
}

// vehicle_status_t: utime >= 0; only known EVENT_* bits; every active bit also latched; a known
// action.
inline Reason check(const vehicle_status_t& m) {
  if (m.utime < 0) return "utime.range";
  if ((m.active & ~vehicle_status_t::EVENT_ALL) != 0) return "active.unknown";
  if ((m.latched & ~vehicle_status_t::EVENT_ALL) != 0) return "latched.unknown";
  if ((m.active & ~m.latched) != 0) return "latched.inconsistent";
  if (m.action < vehicle_status_t::ACTION_NONE || m.action > vehicle_status_t::ACTION_RISE)
    return "action.unknown";
  return nullptr;
}

}  // namespace tiller::checks
