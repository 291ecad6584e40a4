#include "sim/sensor_models.hpp"

#include <GeographicLib/Geocentric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/angles.hpp"
#include "sim/vessel_model.hpp"

namespace tiller::sim {

namespace {
// sqrt(2 ln 2): the CEP of a circular normal error in units of its per-axis sigma.
constexpr double kCepPerSigma = 1.1774100225154747;

double total_std(double white, const BiasParams& b) {
  return std::sqrt(white * white + b.std * b.std);
}
}  // namespace

Vector3 specific_force(const TrueState& s) {
  const Matrix3 r = rotation_zyx(s.eta[3], s.eta[4], s.eta[5]);
  return s.accel_body - r.transpose() * Vector3(0, 0, kGravity);
}

// ---------------------------------------------------------------- GNSS
double GnssModelParams::horizontal_std() const {
  return horizontal_cep_m / kCepPerSigma;
}
double GnssModelParams::horizontal_white_std() const {
  const double s = horizontal_std();
  return std::sqrt(std::max(0.0, s * s - horizontal_bias.std * horizontal_bias.std));
}

GnssModel::GnssModel(const GnssModelParams& p, std::uint64_t seed)
    : p_(p),
      rng_(seed),
      bias_n_(p.horizontal_bias, rng_),
      bias_e_(p.horizontal_bias, rng_),
      datum_(p.datum_latitude_deg, p.datum_longitude_deg, p.datum_altitude_m,
             GeographicLib::Geocentric::WGS84()),
      white_std_(p.horizontal_white_std()) {
  if (p.horizontal_bias.std > p.horizontal_std())
    throw std::invalid_argument("GnssModel: the horizontal bias's std exceeds the CEP's sigma");
}

void GnssModel::step_bias(double dt) {
  bias_n_.step(dt, rng_);
  bias_e_.step(dt, rng_);
}

void GnssModel::sample(TimeUs t, const TrueState& s, bool valid, gnss_fix_t& o) {
  // Every draw is made whether or not there is a fix, so an outage does not shift the noise.
  const double wn = white_std_ * rng_.normal();
  const double we = white_std_ * rng_.normal();
  const double wd = p_.vertical_std_m * rng_.normal();
  const double dvn = p_.velocity_std_m_s * rng_.normal();
  const double dve = p_.velocity_std_m_s * rng_.normal();
  o.utime = t;
  o.gnss_utime = std::max<TimeUs>(t, 0);
  o.device = "sim";
  if (!valid) {
    o.fix_type = gnss_fix_t::FIX_NONE;
    o.satellites = 0;
    o.latitude = o.longitude = o.altitude = o.altitude_msl = 0;
    for (double& v : o.position_std) v = 0;
    o.accuracy_source = gnss_fix_t::ACCURACY_NONE;
    o.hdop = 0;
    o.velocity_valid = false;
    o.speed = o.course = 0;
    return;
  }
  last_ned_ =
      Vector3(s.eta[0] + wn + bias_n_.value(), s.eta[1] + we + bias_e_.value(), s.eta[2] + wd);
  double lat = 0, lon = 0, h = 0;
  // LocalCartesian is east-north-up about the datum.
  datum_.Reverse(last_ned_.y(), last_ned_.x(), -last_ned_.z(), lat, lon, h);
  o.fix_type = gnss_fix_t::FIX_3D;
  o.satellites = static_cast<std::int16_t>(p_.satellites);
  o.latitude = lat;
  o.longitude = lon;
  o.altitude = h;
  o.altitude_msl = h - p_.geoid_separation_m;
  o.position_std[0] = o.position_std[1] = p_.horizontal_std();
  o.position_std[2] = p_.vertical_std_m;
  o.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  o.hdop = p_.hdop;
  const Matrix3 r = rotation_zyx(s.eta[3], s.eta[4], s.eta[5]);
  const Vector3 v = r * s.nu.head<3>();
  const double vn = v.x() + dvn, ve = v.y() + dve;
  o.velocity_valid = true;
  o.speed = std::hypot(vn, ve);
  o.course = o.speed > 0 ? wrap_pi(std::atan2(ve, vn)) : 0.0;
}

// ---------------------------------------------------------------- IMU
ImuModel::ImuModel(const ImuModelParams& p, std::uint64_t seed) : p_(p), rng_(seed) {
  for (auto& b : gyro_bias_) b = Bias(p.gyro_bias, rng_);
  for (auto& b : accel_bias_) b = Bias(p.accel_bias, rng_);
  attitude_bias_[0] = Bias(p.roll_pitch_bias, rng_);
  attitude_bias_[1] = Bias(p.roll_pitch_bias, rng_);
  attitude_bias_[2] = Bias(p.yaw_bias, rng_);
}

void ImuModel::step_bias(double dt) {
  for (auto* set : {&gyro_bias_, &accel_bias_, &attitude_bias_})
    for (auto& b : *set) b.step(dt, rng_);
}

void ImuModel::sample(TimeUs t, const TrueState& s, imu_t& o) {
  o.utime = t;
  const Vector3 f = specific_force(s);
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    o.angular_rate[i] = s.nu[3 + i] + gyro_bias_[k].value() + p_.gyro_std_rad_s * rng_.normal();
    o.specific_force[i] = f[i] + accel_bias_[k].value() + p_.accel_std_m_s2 * rng_.normal();
  }
  const double att_std[3] = {p_.roll_pitch_std_rad, p_.roll_pitch_std_rad, p_.yaw_std_rad};
  double e[3];
  for (int i = 0; i < 3; ++i)
    e[i] = s.eta[3 + i] + attitude_bias_[static_cast<std::size_t>(i)].value() +
           att_std[i] * rng_.normal();
  e[1] = std::clamp(e[1], -M_PI / 2, M_PI / 2);
  // ZYX Euler -> unit quaternion [w x y z], body FRD -> NED.
  const double cr = std::cos(e[0] / 2), sr = std::sin(e[0] / 2);
  const double cp = std::cos(e[1] / 2), sp = std::sin(e[1] / 2);
  const double cy = std::cos(e[2] / 2), sy = std::sin(e[2] / 2);
  o.orientation_valid = p_.orientation;
  o.orientation[0] = p_.orientation ? cr * cp * cy + sr * sp * sy : 1.0;
  o.orientation[1] = p_.orientation ? sr * cp * cy - cr * sp * sy : 0.0;
  o.orientation[2] = p_.orientation ? cr * sp * cy + sr * cp * sy : 0.0;
  o.orientation[3] = p_.orientation ? cr * cp * sy - sr * sp * cy : 0.0;
  for (double* c :
       {o.angular_rate_covariance, o.specific_force_covariance, o.orientation_covariance})
    for (int i = 0; i < 9; ++i) c[i] = 0;
  const double g = total_std(p_.gyro_std_rad_s, p_.gyro_bias);
  const double a = total_std(p_.accel_std_m_s2, p_.accel_bias);
  const double rp = total_std(p_.roll_pitch_std_rad, p_.roll_pitch_bias);
  const double y = total_std(p_.yaw_std_rad, p_.yaw_bias);
  for (int i = 0; i < 3; ++i) {
    o.angular_rate_covariance[4 * i] = g * g;
    o.specific_force_covariance[4 * i] = a * a;
  }
  if (p_.orientation) {
    o.orientation_covariance[0] = o.orientation_covariance[4] = rp * rp;
    o.orientation_covariance[8] = y * y;
  }
  o.heading_is_magnetic = false;
  o.calibration_system = o.calibration_gyro = o.calibration_accel = o.calibration_mag = 3;
  o.temperature = p_.temperature_c;
}

// ---------------------------------------------------------------- heading
HeadingModel::HeadingModel(const HeadingModelParams& p, std::uint64_t seed)
    : p_(p), rng_(seed), bias_(p.bias, rng_) {}

void HeadingModel::sample(TimeUs t, const TrueState& s, heading_t& o) {
  o.utime = t;
  o.heading = wrap_pi(s.eta[5] + bias_.value() + p_.std_rad * rng_.normal());
  const double sd = total_std(p_.std_rad, p_.bias);
  o.variance = std::min(sd * sd, 10.0);
  o.reference = heading_t::REFERENCE_TRUE;
  o.source = heading_t::SOURCE_SIM;
  o.device = "sim";
}

// ---------------------------------------------------------------- pressure
PressureModel::PressureModel(const PressureModelParams& p, std::uint64_t seed)
    : p_(p), rng_(seed), bias_(p.bias, rng_) {}

void PressureModel::sample(TimeUs t, const TrueState& s, pressure_t& o) {
  const double rho_g = p_.water_density * kGravity;
  const double depth = s.eta[2] + p_.depth_offset_m;
  const double p =
      p_.surface_pressure_pa + rho_g * depth + bias_.value() + p_.std_pa * rng_.normal();
  o.utime = t;
  o.pressure = std::max(0.0, p);
  o.temperature = p_.temperature_c;
  o.water_density = p_.water_density;
  o.surface_pressure = p_.surface_pressure_pa;
  o.depth = (o.pressure - p_.surface_pressure_pa) / rho_g;
  const double sd = total_std(p_.std_pa, p_.bias) / rho_g;
  o.depth_variance = std::min(sd * sd, 1e4);
  o.sensor = "sim";
}

// ---------------------------------------------------------------- battery
BatteryModel::BatteryModel(const BatteryModelParams& p, std::uint64_t seed)
    : p_(p), rng_(seed), consumed_ah_(p.initial_consumed_ah) {
  voltage_ = open_circuit_v(consumed_ah_);
}

double BatteryModel::open_circuit_v(double consumed_ah) const {
  const double per_ah = (p_.full_v - p_.empty_v) / p_.capacity_ah;
  return std::max(0.0, p_.full_v - per_ah * consumed_ah);
}

double BatteryModel::load_w(const TrueState& s) const {
  double w = p_.hotel_power_w;
  for (int i = 0; i < s.n_thrusters; ++i)
    w += p_.thruster_w_per_n15 * std::pow(std::abs(s.thrust[i]), 1.5);
  return w;
}

void BatteryModel::step(double dt, const TrueState& s) {
  // The bus draws the load's power P from a source E behind R: V = E - I R, P = V I, so
  // I = (E - sqrt(E^2 - 4 R P)) / (2 R); past the maximum power E^2 / (4 R), I = E / (2 R).
  const double e = open_circuit_v(consumed_ah_);
  const double r = p_.internal_resistance_ohm;
  const double pw = load_w(s);
  double i = 0;
  if (e > 0) {
    if (r > 0) {
      const double disc = e * e - 4 * r * pw;
      i = disc > 0 ? (e - std::sqrt(disc)) / (2 * r) : e / (2 * r);
    } else {
      i = pw / e;
    }
  }
  current_ = i;
  voltage_ = std::max(0.0, e - i * r);
  consumed_ah_ += i * dt / 3600.0;
  consumed_wh_ += voltage_ * i * dt / 3600.0;
}

void BatteryModel::sample(TimeUs t, power_t& o) {
  o.utime = t;
  o.voltage = std::max(0.0, voltage_ + p_.voltage_std_v * rng_.normal());
  o.current = current_ + p_.current_std_a * rng_.normal();
  o.power = o.voltage * o.current;
  o.consumed_charge = consumed_ah_;
  o.consumed_energy = consumed_wh_;
  o.monitor = "sim";
}

// ---------------------------------------------------------------- leak
LeakModel::LeakModel(const LeakModelParams& p) : p_(p) {}

void LeakModel::sample(TimeUs t, TimeUs since_start, leak_t& o) {
  const int n = static_cast<int>(p_.probes.size());
  if (o.n_probes != n || static_cast<int>(o.names.size()) != n) {
    o.n_probes = n;
    o.names = p_.probes;
    o.wet.assign(static_cast<std::size_t>(n), false);
    o.readable.assign(static_cast<std::size_t>(n), true);
  }
  const bool wet = p_.wet_after_s >= 0 && since_start >= from_seconds(p_.wet_after_s);
  o.utime = t;
  for (auto& w : o.wet) w = wet;
  o.any_wet = wet && n > 0;
}

// ---------------------------------------------------------------- DVL
DvlModel::DvlModel(const DvlModelParams& p, std::uint64_t seed) : p_(p), rng_(seed) {
  if (!(p.min_altitude_m >= 0 && p.min_altitude_m < p.max_altitude_m && p.max_altitude_m <= 1e3))
    throw std::invalid_argument("DvlModel: expected 0 <= min_altitude_m < max_altitude_m <= 1000");
}

void DvlModel::sample(TimeUs t, const TrueState& s, dvl_t& o) {
  double n[3];
  for (double& x : n) x = rng_.normal();
  const double altitude = p_.seabed_depth_m - s.eta[2];
  const bool lock = altitude >= p_.min_altitude_m && altitude <= p_.max_altitude_m;
  o.utime = std::max<TimeUs>(t, 0);  // time of validity: the ping's centre
  o.bottom_lock = lock;
  for (double& c : o.velocity_covariance) c = 0;
  const double sd = p_.velocity_std_m_s;
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    o.velocity[i] = lock ? std::clamp(s.nu[i] + p_.bias_m_s[k] + sd * n[i], -20.0, 20.0) : 0.0;
    if (lock) o.velocity_covariance[4 * i] = sd * sd;
  }
  o.fom = lock ? sd : DvlModelParams::kNoLockFom;
  o.altitude = lock ? altitude : -1.0;
  o.beams_valid = lock ? 4 : 0;
  o.status = 0;
  o.sensor = "sim";
}

}  // namespace tiller::sim
