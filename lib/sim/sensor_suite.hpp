// The simulator's sensors together (tiller-sim publishes them when given a sensors file,
// config/sim/sensors/*.yaml): each sensor's model (sensor_models.hpp) sampled on its own grid
// of simulated time (multiples of its period), each sample held for its latency, some lost to
// dropouts, and published on the channel its real driver uses:
//   TILLER_GNSS (and/or NMEA GGA/GSA/GST/RMC to a sink: the pty gpsd reads), TILLER_IMU,
//   TILLER_HEADING, TILLER_PRESSURE, TILLER_POWER, TILLER_LEAK, TILLER_DVL.
// GNSS outages (config `outages`, tiller-sim --gnss-outage) make the receiver report no fix;
// DVL outages (`dvl.outages`, --dvl-outage) publish no dvl_t at all (the driver stopped);
// a leak (`leak.wet_after_s`, --leak-at) turns every probe wet. Times are relative to the
// simulator's start. Seeded: same seed, same calls, same messages; no heap per step.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/channels.hpp"
#include "sim/nmea.hpp"
#include "sim/sensor_models.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sim {

struct GnssOutage {
  TimeUs start_us = 0, end_us = 0;  // [start, end) after the simulator's start
};
using DvlOutage = GnssOutage;

struct SensorParams {
  bool enabled = false;  // false: no sensor messages (the simulator publishes odometry only)
  std::string file;      // where they were loaded from
  SensorTiming gnss_timing, imu_timing, heading_timing, pressure_timing, power_timing, leak_timing;
  GnssModelParams gnss;
  bool gnss_lcm = true;    // TILLER_GNSS from the simulator
  bool gnss_nmea = false;  // NMEA sentences to the sink (tiller-sim: a pseudo-terminal for gpsd)
  std::vector<GnssOutage> gnss_outages;
  ImuModelParams imu;
  HeadingModelParams heading;
  PressureModelParams pressure;
  BatteryModelParams power;
  LeakModelParams leak;
  // The DVL samples at the first simulator step at or after each multiple of its period (8 Hz
  // with 10 ms steps: 120 or 130 ms apart, 8 a second), so its period need not be a whole
  // number of steps.
  SensorTiming dvl_timing;
  DvlModelParams dvl;
  std::vector<DvlOutage> dvl_outages;
};

// Reads a sensors file strictly (every key checked, errors name file, line, key, expectation).
// `step_us` is the simulator's step: every period must be a whole number of steps.
SensorParams load_sensor_params(const config::Value& root, TimeUs step_us);
SensorParams load_sensor_file(const std::string& path, TimeUs step_us);

// Where NMEA text goes (tiller-sim: a pseudo-terminal, lib/sim/nmea_pty.hpp).
class NmeaSink {
 public:
  virtual ~NmeaSink() = default;
  virtual void write(const char* data, std::size_t n) = 0;
};

class SensorSuite {
 public:
  // Throws std::invalid_argument for a model's inconsistent parameters.
  SensorSuite(const SensorParams& p, std::uint64_t seed);
  bool enabled() const { return p_.enabled; }
  const SensorParams& params() const { return p_; }
  void set_nmea_sink(NmeaSink* s) { sink_ = s; }
  // Where each lost sample is counted (one counter per sensor; nullptr: not counted).
  void set_drop_counters(std::int64_t* gnss, std::int64_t* imu, std::int64_t* heading,
                         std::int64_t* pressure, std::int64_t* power, std::int64_t* leak,
                         std::int64_t* dvl = nullptr);

  // After each simulator step: the true state at time t, dt seconds after the previous step.
  void step(TimeUs t, double dt, const TrueState& s);
  // Hands every message due at `now` to pub(channel, message) (and NMEA to the sink).
  template <class Pub>
  void release(TimeUs now, Pub&& pub);

  const BatteryModel& battery() const { return battery_; }
  const GnssModel& gnss() const { return gnss_model_; }
  bool gnss_in_outage(TimeUs since_start) const;
  bool dvl_in_outage(TimeUs since_start) const;

 private:
  struct Slot {
    TimeUs next = 0, last = -1;
    std::int64_t* dropped = nullptr;
  };
  // Due at t (a multiple of the period reached): advances the slot; sets dt_s since its last.
  bool due(Slot& slot, const SensorTiming& timing, TimeUs t, double& dt_s);
  bool lost(Slot& slot, const SensorTiming& timing, SensorRng& rng);
  void write_nmea(const gnss_fix_t& f);

  SensorParams p_;
  GnssModel gnss_model_;
  ImuModel imu_model_;
  HeadingModel heading_model_;
  PressureModel pressure_model_;
  BatteryModel battery_;
  LeakModel leak_model_;
  DvlModel dvl_model_;
  SensorRng dropout_rng_;
  SensorRng dvl_dropout_rng_;  // the DVL's own: adding it leaves the others' dropouts as they were
  NmeaSink* sink_ = nullptr;
  bool started_ = false;
  TimeUs start_ = 0;
  Slot gnss_s_, imu_s_, heading_s_, pressure_s_, power_s_, leak_s_, dvl_s_;
  gnss_fix_t gnss_msg_{};
  imu_t imu_msg_{};
  heading_t heading_msg_{};
  pressure_t pressure_msg_{};
  power_t power_msg_{};
  leak_t leak_msg_{};
  dvl_t dvl_msg_{};
  DelayLine<gnss_fix_t> gnss_q_;
  DelayLine<imu_t> imu_q_;
  DelayLine<heading_t> heading_q_;
  DelayLine<pressure_t> pressure_q_;
  DelayLine<power_t> power_q_;
  DelayLine<leak_t> leak_q_;
  DelayLine<dvl_t> dvl_q_;
  char nmea_[nmea::kMaxEpochBytes];
};

template <class Pub>
void SensorSuite::release(TimeUs now, Pub&& pub) {
  gnss_q_.release(now, [&](gnss_fix_t& m) {
    m.utime = now;  // when the fix reaches the host
    if (p_.gnss_lcm) pub(channels::kGnss, m);
    if (p_.gnss_nmea) write_nmea(m);
  });
  imu_q_.release(now, [&](const imu_t& m) { pub(channels::kImu, m); });
  heading_q_.release(now, [&](const heading_t& m) { pub(channels::kHeading, m); });
  pressure_q_.release(now, [&](const pressure_t& m) { pub(channels::kPressure, m); });
  power_q_.release(now, [&](const power_t& m) { pub(channels::kPower, m); });
  leak_q_.release(now, [&](const leak_t& m) { pub(channels::kLeak, m); });
  dvl_q_.release(now, [&](const dvl_t& m) { pub(channels::kDvl, m); });
}

}  // namespace tiller::sim
