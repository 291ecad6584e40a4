// The simulated sensors: one model per sensor, each turning the simulator's true state at a
// sample time into the message its real driver publishes (the same type, the same channel):
//   GnssModel      gnss_fix_t   antenna at the reference point; NED -> WGS84 through
//                               GeographicLib::LocalCartesian about a datum; white noise sized
//                               by a CEP, plus a wandering horizontal bias
//   ImuModel       imu_t        gyro and accelerometer (white noise + bias, body FRD), and a
//                               fused orientation (BNO055-like: roll/pitch/yaw errors)
//   HeadingModel   heading_t    heading with white noise + bias (true north)
//   PressureModel  pressure_t   absolute pressure from depth, density and surface pressure
//   BatteryModel   power_t      a battery: thruster power from thrust (P = k |T|^1.5), voltage
//                               sagging with the charge drawn and the load (OCV - I R)
//   LeakModel      leak_t       dry probes, until a configured time makes them wet
//   DvlModel       dvl_t        bottom-track velocity: the true body-FRD velocity over ground
//                               plus white noise and a constant bias per axis; the altitude
//                               above a flat seabed; no bottom lock outside its altitude range
// Each model takes the time and the state as arguments and draws from its own seeded generator
// (sensor_noise.hpp); no clock, no heap per sample. The rates, latencies and dropouts are
// applied by SensorSuite (sensor_suite.hpp).
#pragma once

#include <GeographicLib/LocalCartesian.hpp>

#include <array>
#include <string>
#include <vector>

#include <tiller/dvl_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/pressure_t.hpp>

#include "sim/dynamics.hpp"
#include "sim/sensor_noise.hpp"

namespace tiller::sim {

inline constexpr double kGravity = 9.80665;  // m/s^2, standard gravity (as pressure_t's depth)

// What the sensors sense at one instant.
struct TrueState {
  Vector6 eta = Vector6::Zero();  // [n e d] m NED, [roll pitch yaw] rad (ZYX)
  Vector6 nu = Vector6::Zero();   // [u v w] m/s, [p q r] rad/s, body FRD over ground
  // Acceleration of the body's reference point relative to NED, in body FRD (m/s^2):
  // d/dt [u v w] + omega x [u v w].
  Vector3 accel_body = Vector3::Zero();
  const double* thrust = nullptr;  // N per thruster (n_thrusters of them)
  int n_thrusters = 0;
};

// Specific force an accelerometer at the reference point reads (body FRD, m/s^2): the
// acceleration minus gravity, R^T ([a_ned] - [0 0 g]); level at rest [0 0 -g].
Vector3 specific_force(const TrueState& s);

// ---------------------------------------------------------------- GNSS
struct GnssModelParams {
  double datum_latitude_deg = 59.437, datum_longitude_deg = 10.6612;  // NED origin, WGS84
  double datum_altitude_m = 0;             // m above the ellipsoid at the NED origin
  double geoid_separation_m = 0;           // ellipsoid - MSL (NMEA GGA's field), m
  double horizontal_cep_m = 2.5;           // 50 % of horizontal errors within this radius
  BiasParams horizontal_bias{0.2, 120.0};  // per axis (north, east), part of the CEP's error
  double vertical_std_m = 4.0;             // white, m
  double velocity_std_m_s = 0.05;          // per axis (north, east), white
  int satellites = 10;
  double hdop = 0.9;
  // Per axis 1-sigma of the whole horizontal error: a circular normal error has
  // CEP = sqrt(2 ln 2) sigma = 1.1774 sigma.
  double horizontal_std() const;
  double horizontal_white_std() const;  // of the white part: sqrt(std^2 - bias std^2)
};

class GnssModel {
 public:
  // Throws std::invalid_argument when the bias alone exceeds the CEP's error.
  GnssModel(const GnssModelParams& p, std::uint64_t seed);
  // A fix of the state at time t (us since 1970 UTC for gnss_utime); `valid` false: no fix
  // (an outage: FIX_NONE, zeros). Also keeps the north/east/down position it reported.
  void sample(TimeUs t, const TrueState& s, bool valid, gnss_fix_t& out);
  void step_bias(double dt);
  const GnssModelParams& params() const { return p_; }
  const Vector3& last_ned() const { return last_ned_; }  // what the last fix said, NED m

 private:
  GnssModelParams p_;
  SensorRng rng_;
  Bias bias_n_, bias_e_;
  GeographicLib::LocalCartesian datum_;
  double white_std_;
  Vector3 last_ned_ = Vector3::Zero();
};

// ---------------------------------------------------------------- IMU
struct ImuModelParams {
  double gyro_std_rad_s = 0.0017;  // per sample, white (0.1 deg/s)
  BiasParams gyro_bias{0.0017, 300.0};
  double accel_std_m_s2 = 0.03;
  BiasParams accel_bias{0.05, 300.0};
  bool orientation = true;             // the device fuses an attitude (orientation_valid)
  double roll_pitch_std_rad = 0.0035;  // white (0.2 deg)
  BiasParams roll_pitch_bias{0.0052, 120.0};
  double yaw_std_rad = 0.0087;  // white (0.5 deg)
  BiasParams yaw_bias{0.0087, 120.0};
  double temperature_c = 20;
};

class ImuModel {
 public:
  ImuModel(const ImuModelParams& p, std::uint64_t seed);
  void sample(TimeUs t, const TrueState& s, imu_t& out);
  void step_bias(double dt);
  const ImuModelParams& params() const { return p_; }

 private:
  ImuModelParams p_;
  SensorRng rng_;
  std::array<Bias, 3> gyro_bias_, accel_bias_, attitude_bias_;
};

// ---------------------------------------------------------------- heading
struct HeadingModelParams {
  double std_rad = 0.0175;  // white (1 deg)
  BiasParams bias{0.0087, 120.0};
};

class HeadingModel {
 public:
  HeadingModel(const HeadingModelParams& p, std::uint64_t seed);
  void sample(TimeUs t, const TrueState& s, heading_t& out);
  void step_bias(double dt) { bias_.step(dt, rng_); }

 private:
  HeadingModelParams p_;
  SensorRng rng_;
  Bias bias_;
};

// ---------------------------------------------------------------- pressure
struct PressureModelParams {
  double water_density = 1025;          // kg/m^3 (sea; fresh 997)
  double surface_pressure_pa = 101325;  // Pa at the surface
  double std_pa = 20;                   // white (MS5837-30BA at OSR 8192: 0.2 mbar)
  BiasParams bias{0, 0};                // Pa
  double depth_offset_m = 0;            // the sensor below (+) the reference point, m
  double temperature_c = 15;
};

class PressureModel {
 public:
  PressureModel(const PressureModelParams& p, std::uint64_t seed);
  void sample(TimeUs t, const TrueState& s, pressure_t& out);
  void step_bias(double dt) { bias_.step(dt, rng_); }

 private:
  PressureModelParams p_;
  SensorRng rng_;
  Bias bias_;
};

// ---------------------------------------------------------------- battery and power monitor
struct BatteryModelParams {
  double capacity_ah = 18;               // to empty
  double full_v = 16.8, empty_v = 13.2;  // open-circuit voltage at full and empty (linear between)
  double internal_resistance_ohm = 0.03;
  double hotel_power_w = 15;        // computers, sensors, radio
  double thruster_w_per_n15 = 1.1;  // W per N^1.5 of each thruster's |thrust| (T200 at 16 V)
  double initial_consumed_ah = 0;   // drawn before the start (a battery not full)
  double voltage_std_v = 0.01, current_std_a = 0.05;  // the monitor's white noise
};

class BatteryModel {
 public:
  BatteryModel(const BatteryModelParams& p, std::uint64_t seed);
  // Draws the load of state s for dt seconds (called every simulator step).
  void step(double dt, const TrueState& s);
  void sample(TimeUs t, power_t& out);
  // The bus voltage (V) and current (A) now, without the monitor's noise.
  double voltage() const { return voltage_; }
  double current() const { return current_; }
  double consumed_ah() const { return consumed_ah_; }
  double load_w(const TrueState& s) const;
  // Open-circuit voltage after `consumed_ah` drawn (linear in the charge; below empty it goes
  // on falling at the same slope, floored at 0).
  double open_circuit_v(double consumed_ah) const;

 private:
  BatteryModelParams p_;
  SensorRng rng_;
  double consumed_ah_, consumed_wh_ = 0, voltage_, current_ = 0;
};

// ---------------------------------------------------------------- leak probes
struct LeakModelParams {
  std::vector<std::string> probes{"main_tube"};
  double wet_after_s = -1;  // s after the start when every probe turns wet; < 0 never
};

class LeakModel {
 public:
  explicit LeakModel(const LeakModelParams& p);
  // `since_start`: us since the simulator started.
  void sample(TimeUs t, TimeUs since_start, leak_t& out);

 private:
  LeakModelParams p_;
};

// ---------------------------------------------------------------- DVL
// A Doppler velocity log looking down (Water Linked DVL-A50 class) at the reference point,
// its axes the body's (the driver has applied the mounting rotation). The seabed is flat at
// seabed_depth_m; the altitude is seabed_depth_m - depth. With the altitude in
// [min_altitude_m, max_altitude_m] it has bottom lock: velocity = nu[0..2] (over ground, not
// relative to the water) + bias + std * N(0, 1) per axis, fom = std, covariance diagonal std^2,
// 4 beams valid. Outside it: no lock (velocity 0, altitude -1, covariance 0, fom kNoLockFom,
// beams_valid 0), as dvl_t's contract asks.
struct DvlModelParams {
  double velocity_std_m_s = 0.005;           // white, per axis, 1-sigma (also the reported fom)
  std::array<double, 3> bias_m_s{};          // constant, per axis (u v w), m/s
  double seabed_depth_m = 20;                // m below the surface (NED d = 0), flat bottom
  double min_altitude_m = 0.05;              // A50: 0.05 m
  double max_altitude_m = 50;                // A50: 50 m
  static constexpr double kNoLockFom = 100;  // dvl_t's maximum: no usable velocity
};

class DvlModel {
 public:
  DvlModel(const DvlModelParams& p, std::uint64_t seed);
  // Three normals are drawn per sample whether or not there is a lock, so losing the bottom
  // does not shift the noise of later samples.
  void sample(TimeUs t, const TrueState& s, dvl_t& out);
  const DvlModelParams& params() const { return p_; }

 private:
  DvlModelParams p_;
  SensorRng rng_;
};

}  // namespace tiller::sim
