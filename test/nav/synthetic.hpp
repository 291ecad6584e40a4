// Synthetic sensor streams for tiller-nav's tests and benchmark: a boat (or ROV) on a known
// path (straight legs and steady turns at constant speed through the water, body FRD, heading in
// NED; optionally in a constant current, the hull with no sway through the water), and seeded
// noisy GNSS, IMU, heading and pressure messages made from it, as the drivers publish them.
// The default noise is a 2.5 m CEP GNSS at 5 Hz (1-sigma 2.5 / 1.1774 = 2.12 m per axis) with
// 0.1 m/s velocity noise, and a consumer IMU: gyro bias 0.005 rad/s (0.29 deg/s), gyro noise
// 0.005 rad/s per sample at 100 Hz, accelerometer bias 0.03 m/s^2 and noise 0.03 m/s^2, a fused
// heading at 10 Hz with 2 deg white noise, roll and pitch 0.5 deg. Everything is deterministic for
// a seed.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <GeographicLib/LocalCartesian.hpp>
#include <tiller/dvl_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/pressure_t.hpp>

#include "core/angles.hpp"
#include "core/time.hpp"

namespace tiller::nav::test {

inline constexpr double kLat0 = 59.43, kLon0 = 10.47;  // the truth's origin (WGS84 deg)

struct Truth {
  double n = 0, e = 0, d = 0, psi = 0;  // m, rad
  double u = 1.5, r = 0;                // m/s, rad/s (body; u through the water, no sway)
  double current_n = 0, current_e = 0;  // m/s, NED: the water's velocity over ground (constant)
};

struct Noise {
  double gnss_std_m = 2.5 / 1.1774;
  double gnss_velocity_std = 0.1;
  double gyro_bias = 0.005, gyro_std = 0.005;  // rad/s
  double accel_bias = 0.03, accel_std = 0.03;  // m/s^2 (forward, starboard)
  double heading_std = deg_to_rad(2.0);
  double attitude_std = deg_to_rad(0.5);
  double depth_std = 0.02;  // m
  double dvl_std = 0.005;   // m/s per axis (a DVL-A50 class bottom track)
};

// A leg: for `duration_s`, turn at `r` rad/s (0: straight).
struct Leg {
  double duration_s;
  double r;
};

class Synthetic {
 public:
  explicit Synthetic(std::vector<Leg> legs, unsigned seed = 1, Noise noise = {})
      : legs_(std::move(legs)), noise_(noise), rng_(seed), datum_(kLat0, kLon0, 0) {}

  const Truth& truth() const { return truth_; }
  double duration_s() const {
    double s = 0;
    for (const auto& l : legs_) s += l.duration_s;
    return s;
  }
  // Moves the truth on to time t (us), in 1 ms steps.
  void advance_to(TimeUs t) {
    for (; now_ + 1000 <= t; now_ += 1000) {
      truth_.r = rate_at(to_seconds(now_));
      const double psi_mid = truth_.psi + 0.5 * truth_.r * 1e-3;
      truth_.n += (truth_.u * std::cos(psi_mid) + truth_.current_n) * 1e-3;
      truth_.e += (truth_.u * std::sin(psi_mid) + truth_.current_e) * 1e-3;
      truth_.psi = wrap_pi(truth_.psi + truth_.r * 1e-3);
    }
    truth_.r = rate_at(to_seconds(now_));
  }

  gnss_fix_t gnss(TimeUs t) {
    gnss_fix_t m{};
    m.utime = t;
    m.fix_type = gnss_fix_t::FIX_3D;
    m.satellites = 9;
    const double n = truth_.n + g(noise_.gnss_std_m), e = truth_.e + g(noise_.gnss_std_m);
    double h = 0;
    datum_.Reverse(e, n, 0.0, m.latitude, m.longitude, h);
    m.altitude = h;
    m.position_std[0] = m.position_std[1] = noise_.gnss_std_m;
    m.position_std[2] = 2 * noise_.gnss_std_m;
    m.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
    m.hdop = 1.0;
    const double vn =
        truth_.u * std::cos(truth_.psi) + truth_.current_n + g(noise_.gnss_velocity_std);
    const double ve =
        truth_.u * std::sin(truth_.psi) + truth_.current_e + g(noise_.gnss_velocity_std);
    m.velocity_valid = true;
    m.speed = std::hypot(vn, ve);
    m.course = wrap_pi(std::atan2(ve, vn));
    m.device = "synthetic";
    return m;
  }
  imu_t imu(TimeUs t) {
    imu_t m{};
    m.utime = t;
    m.angular_rate[0] = g(noise_.gyro_std);
    m.angular_rate[1] = g(noise_.gyro_std);
    m.angular_rate[2] = truth_.r + noise_.gyro_bias + g(noise_.gyro_std);
    // Level, constant speed: the body's acceleration is the turn's centripetal r u, starboard
    // (a constant current adds none).
    m.specific_force[0] = noise_.accel_bias + g(noise_.accel_std);
    m.specific_force[1] = truth_.u * truth_.r - noise_.accel_bias + g(noise_.accel_std);
    m.specific_force[2] = -9.80665;
    const double roll = g(noise_.attitude_std), pitch = g(noise_.attitude_std);
    const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
    const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
    const double cy = std::cos(truth_.psi / 2), sy = std::sin(truth_.psi / 2);
    m.orientation_valid = true;
    m.orientation[0] = cr * cp * cy + sr * sp * sy;
    m.orientation[1] = sr * cp * cy - cr * sp * sy;
    m.orientation[2] = cr * sp * cy + sr * cp * sy;
    m.orientation[3] = cr * cp * sy - sr * sp * cy;
    const double av = noise_.attitude_std * noise_.attitude_std;
    m.orientation_covariance[0] = m.orientation_covariance[4] = av;
    m.orientation_covariance[8] = noise_.heading_std * noise_.heading_std;
    const double rv = noise_.gyro_std * noise_.gyro_std;
    m.angular_rate_covariance[0] = m.angular_rate_covariance[4] = m.angular_rate_covariance[8] = rv;
    m.calibration_system = m.calibration_gyro = m.calibration_accel = m.calibration_mag = 3;
    m.temperature = 20;
    return m;
  }
  heading_t heading(TimeUs t) {
    heading_t m{};
    m.utime = t;
    m.heading = wrap_pi(truth_.psi + g(noise_.heading_std));
    m.variance = noise_.heading_std * noise_.heading_std;
    m.reference = heading_t::REFERENCE_TRUE;
    m.source = heading_t::SOURCE_AHRS;
    m.device = "synthetic";
    return m;
  }
  // The DVL's bottom-track velocity: over ground in body FRD (u through the water plus the
  // current turned into the body; level).
  dvl_t dvl(TimeUs t) {
    dvl_t m{};
    m.utime = t;
    m.bottom_lock = true;
    const double c = std::cos(truth_.psi), s = std::sin(truth_.psi);
    m.velocity[0] = truth_.u + c * truth_.current_n + s * truth_.current_e + g(noise_.dvl_std);
    m.velocity[1] = -s * truth_.current_n + c * truth_.current_e + g(noise_.dvl_std);
    m.velocity[2] = g(noise_.dvl_std);
    for (int i = 0; i < 3; ++i) m.velocity_covariance[4 * i] = noise_.dvl_std * noise_.dvl_std;
    m.fom = noise_.dvl_std;
    m.altitude = 4.0;
    m.beams_valid = 4;
    m.sensor = "synthetic";
    return m;
  }
  pressure_t pressure(TimeUs t) {
    pressure_t m{};
    m.utime = t;
    m.depth = truth_.d + g(noise_.depth_std);
    m.water_density = 1025;
    m.surface_pressure = 101325;
    m.pressure = m.surface_pressure + m.depth * 1025 * 9.80665;
    m.temperature = 10;
    m.depth_variance = noise_.depth_std * noise_.depth_std;
    m.sensor = "synthetic";
    return m;
  }
  Truth& mutable_truth() { return truth_; }

 private:
  double rate_at(double s) const {
    for (const auto& l : legs_) {
      if (s < l.duration_s) return l.r;
      s -= l.duration_s;
    }
    return 0;
  }
  double g(double sigma) { return sigma * std::normal_distribution<double>(0.0, 1.0)(rng_); }

  std::vector<Leg> legs_;
  Noise noise_;
  std::mt19937 rng_;
  GeographicLib::LocalCartesian datum_;
  Truth truth_;
  TimeUs now_ = 0;
};

}  // namespace tiller::nav::test
