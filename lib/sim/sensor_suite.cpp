#include "sim/sensor_suite.hpp"

#include <cmath>

namespace tiller::sim {

namespace {
// SplitMix64 (Steele, Lea, Flood 2014): a well-mixed seed per sensor from one simulator seed.
std::uint64_t mix(std::uint64_t seed, std::uint64_t which) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (which + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
}  // namespace

SensorSuite::SensorSuite(const SensorParams& p, std::uint64_t seed)
    : p_(p),
      gnss_model_(p.gnss, mix(seed, 1)),
      imu_model_(p.imu, mix(seed, 2)),
      heading_model_(p.heading, mix(seed, 3)),
      pressure_model_(p.pressure, mix(seed, 4)),
      battery_(p.power, mix(seed, 5)),
      leak_model_(p.leak),
      dvl_model_(p.dvl, mix(seed, 7)),
      dropout_rng_(mix(seed, 6)),
      dvl_dropout_rng_(mix(seed, 8)) {
  // The leak message holds a vector of names: shape every slot now (no allocation per sample).
  leak_model_.sample(0, 0, leak_msg_);
  leak_q_.reserve_like(leak_msg_);
  dvl_msg_.sensor = "sim";
  dvl_q_.reserve_like(dvl_msg_);
}

void SensorSuite::set_drop_counters(std::int64_t* gnss, std::int64_t* imu, std::int64_t* heading,
                                    std::int64_t* pressure, std::int64_t* power, std::int64_t* leak,
                                    std::int64_t* dvl) {
  gnss_s_.dropped = gnss;
  imu_s_.dropped = imu;
  heading_s_.dropped = heading;
  pressure_s_.dropped = pressure;
  power_s_.dropped = power;
  leak_s_.dropped = leak;
  dvl_s_.dropped = dvl;
}

bool SensorSuite::gnss_in_outage(TimeUs since_start) const {
  for (const auto& o : p_.gnss_outages)
    if (since_start >= o.start_us && since_start < o.end_us) return true;
  return false;
}

bool SensorSuite::dvl_in_outage(TimeUs since_start) const {
  for (const auto& o : p_.dvl_outages)
    if (since_start >= o.start_us && since_start < o.end_us) return true;
  return false;
}

bool SensorSuite::due(Slot& slot, const SensorTiming& timing, TimeUs t, double& dt_s) {
  if (!timing.enabled) return false;
  // The first sample at the first multiple of the period: every sample is on the sensor's grid.
  if (slot.last < 0 && slot.next == 0)
    slot.next = (t + timing.period_us - 1) / timing.period_us * timing.period_us;
  if (t < slot.next) return false;
  slot.next = (t / timing.period_us + 1) * timing.period_us;
  dt_s = slot.last < 0 ? 0.0 : to_seconds(t - slot.last);
  slot.last = t;
  return true;
}

bool SensorSuite::lost(Slot& slot, const SensorTiming& timing, SensorRng& rng) {
  if (!(timing.dropout_probability > 0) || rng.uniform() >= timing.dropout_probability)
    return false;
  if (slot.dropped) ++*slot.dropped;
  return true;
}

void SensorSuite::step(TimeUs t, double dt, const TrueState& s) {
  if (!p_.enabled) return;
  if (!started_) {
    started_ = true;
    start_ = t - from_seconds(dt);
  }
  const TimeUs since = t - start_;
  if (p_.power_timing.enabled) battery_.step(dt, s);
  double dts = 0;
  // A sample that is lost was still taken (its noise drawn), so dropouts do not shift the noise.
  if (due(gnss_s_, p_.gnss_timing, t, dts)) {
    gnss_model_.step_bias(dts);
    gnss_model_.sample(t, s, !gnss_in_outage(since), gnss_msg_);
    if (!lost(gnss_s_, p_.gnss_timing, dropout_rng_) &&
        !gnss_q_.push(gnss_msg_, t + p_.gnss_timing.latency_us))
      if (gnss_s_.dropped) ++*gnss_s_.dropped;
  }
  if (due(imu_s_, p_.imu_timing, t, dts)) {
    imu_model_.step_bias(dts);
    imu_model_.sample(t, s, imu_msg_);
    if (!lost(imu_s_, p_.imu_timing, dropout_rng_))
      imu_q_.push(imu_msg_, t + p_.imu_timing.latency_us);
  }
  if (due(heading_s_, p_.heading_timing, t, dts)) {
    heading_model_.step_bias(dts);
    heading_model_.sample(t, s, heading_msg_);
    if (!lost(heading_s_, p_.heading_timing, dropout_rng_))
      heading_q_.push(heading_msg_, t + p_.heading_timing.latency_us);
  }
  if (due(pressure_s_, p_.pressure_timing, t, dts)) {
    pressure_model_.step_bias(dts);
    pressure_model_.sample(t, s, pressure_msg_);
    if (!lost(pressure_s_, p_.pressure_timing, dropout_rng_))
      pressure_q_.push(pressure_msg_, t + p_.pressure_timing.latency_us);
  }
  if (due(power_s_, p_.power_timing, t, dts)) {
    battery_.sample(t, power_msg_);
    if (!lost(power_s_, p_.power_timing, dropout_rng_))
      power_q_.push(power_msg_, t + p_.power_timing.latency_us);
  }
  if (due(leak_s_, p_.leak_timing, t, dts)) {
    leak_model_.sample(t, since, leak_msg_);
    if (!lost(leak_s_, p_.leak_timing, dropout_rng_))
      leak_q_.push(leak_msg_, t + p_.leak_timing.latency_us);
  }
  // In an outage the DVL is sampled (its noise drawn) but nothing is published: the driver is
  // silent, not reporting a lost lock.
  if (due(dvl_s_, p_.dvl_timing, t, dts)) {
    dvl_model_.sample(t, s, dvl_msg_);
    if (!dvl_in_outage(since) && !lost(dvl_s_, p_.dvl_timing, dvl_dropout_rng_) &&
        !dvl_q_.push(dvl_msg_, t + p_.dvl_timing.latency_us))
      if (dvl_s_.dropped) ++*dvl_s_.dropped;
  }
}

void SensorSuite::write_nmea(const gnss_fix_t& m) {
  if (sink_ == nullptr) return;
  nmea::Fix f;
  f.utc_us = m.gnss_utime;
  f.valid = m.fix_type != gnss_fix_t::FIX_NONE;
  f.latitude_deg = m.latitude;
  f.longitude_deg = m.longitude;
  f.altitude_msl_m = m.altitude_msl;
  f.geoid_separation_m = p_.gnss.geoid_separation_m;
  f.satellites = m.satellites;
  f.hdop = p_.gnss.hdop;
  f.vdop = 1.5 * p_.gnss.hdop;
  f.pdop = std::hypot(f.hdop, f.vdop);
  f.speed_m_s = m.speed;
  f.course_rad = m.course;
  f.std_north_m = m.position_std[0];
  f.std_east_m = m.position_std[1];
  f.std_up_m = m.position_std[2];
  const std::size_t n = nmea::epoch(f, nmea_, sizeof nmea_);
  if (n > 0) sink_->write(nmea_, n);
}

}  // namespace tiller::sim
