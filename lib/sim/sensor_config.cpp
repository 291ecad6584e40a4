// Loading a simulated sensors file (config/sim/sensors/*.yaml) into SensorParams: every key is
// read and range-checked whether or not its sensor is enabled (a typo is refused either way).
#include <cmath>
#include <string>

#include "core/config.hpp"
#include "sim/sensor_suite.hpp"

namespace tiller::sim {

namespace {

using config::Range;
using config::Value;

constexpr double kDegToRad = M_PI / 180.0;

// `whole_steps` false (the DVL): any rate in `rates`; it samples at the first step at or after
// each multiple of its period.
SensorTiming timing(const Value& s, double default_hz, TimeUs step_us, bool whole_steps = true,
                    Range rates = {0.01, 1000.0}) {
  SensorTiming t;
  t.enabled = s.boolean("enabled");
  const double hz = s.number_or("rate_hz", default_hz, rates);
  t.period_us = from_hz(hz);
  if (whole_steps && t.period_us % step_us != 0)
    s.at("rate_hz").fail("a rate whose period is a whole number of the simulator's steps (" +
                         std::to_string(step_us) + " us)");
  const double max_latency = to_seconds(t.period_us) * SensorTiming::kMaxLatencyPeriods;
  t.latency_us = from_seconds(s.number_or("latency_s", 0.0, {0.0, max_latency}));
  t.dropout_probability = s.number_or("dropout_probability", 0.0, {0.0, 0.99});
  return t;
}

// `key: {<std_key>: X, tau_s: T}`; X scaled by `scale` (degrees to radians, ...).
BiasParams bias(const Value& s, std::string_view key, std::string_view std_key, double scale,
                double max_std, BiasParams fallback) {
  const auto b = s.find(key);
  if (!b) return fallback;
  BiasParams p;
  p.std = b->number(std_key, {0.0, max_std}) * scale;
  p.tau_s = b->number_or("tau_s", 0.0, {0.0, 1e6});
  return p;
}

void load_gnss_rest(const Value& s, SensorParams& p);

void load_gnss(const Value& s, const Value& root, TimeUs step_us, SensorParams& p) {
  p.gnss_timing = timing(s, 5.0, step_us);
  GnssModelParams& g = p.gnss;
  // The datum is required when the GNSS is on (a disabled GNSS keeps the default one).
  if (!p.gnss_timing.enabled && !root.has("datum")) return load_gnss_rest(s, p);
  const Value d = root.at("datum", "a map with latitude_deg, longitude_deg and altitude_m");
  g.datum_latitude_deg = d.number("latitude_deg", {-89.9, 89.9});
  g.datum_longitude_deg = d.number("longitude_deg", {-180.0, 180.0});
  g.datum_altitude_m = d.number("altitude_m", {-1e3, 1e4});
  g.geoid_separation_m = d.number_or("geoid_separation_m", 0.0, {-200.0, 200.0});
  load_gnss_rest(s, p);
}

void load_gnss_rest(const Value& s, SensorParams& p) {
  GnssModelParams& g = p.gnss;
  g.horizontal_cep_m = s.number_or("horizontal_cep_m", g.horizontal_cep_m, {1e-3, 100.0});
  g.horizontal_bias = bias(s, "horizontal_bias", "std_m", 1.0, 100.0, g.horizontal_bias);
  if (g.horizontal_bias.std > g.horizontal_std())
    s.at("horizontal_bias")
        .fail(
            "a std_m at most the CEP's per-axis sigma (horizontal_cep_m / "
            "1.1774 = " +
            std::to_string(g.horizontal_std()) + " m)");
  g.vertical_std_m = s.number_or("vertical_std_m", g.vertical_std_m, {0.0, 100.0});
  g.velocity_std_m_s = s.number_or("velocity_std_m_s", g.velocity_std_m_s, {0.0, 10.0});
  g.satellites = static_cast<int>(s.integer_or("satellites", g.satellites, 4, 12));
  g.hdop = s.number_or("hdop", g.hdop, {0.5, 50.0});
  const std::string out = s.choice_or("output", "lcm", {"lcm", "nmea", "both"});
  p.gnss_lcm = out != "nmea";
  p.gnss_nmea = out != "lcm";
  if (const auto outs = s.find("outages")) {
    if (!outs->is_sequence()) outs->fail("a list of {start_s, duration_s}");
    for (const auto& o : outs->items()) {
      const double start = o.number("start_s", {0.0, 1e7});
      const double dur = o.number("duration_s", {0.0, 1e7});
      p.gnss_outages.push_back({from_seconds(start), from_seconds(start + dur)});
    }
  }
}

void load_imu(const Value& s, TimeUs step_us, SensorParams& p) {
  p.imu_timing = timing(s, 100.0, step_us);
  ImuModelParams& m = p.imu;
  m.gyro_std_rad_s =
      s.number_or("gyro_std_deg_s", m.gyro_std_rad_s / kDegToRad, {0.0, 100.0}) * kDegToRad;
  m.gyro_bias = bias(s, "gyro_bias", "std_deg_s", kDegToRad, 100.0, m.gyro_bias);
  m.accel_std_m_s2 = s.number_or("accel_std_m_s2", m.accel_std_m_s2, {0.0, 10.0});
  m.accel_bias = bias(s, "accel_bias", "std_m_s2", 1.0, 10.0, m.accel_bias);
  m.orientation = s.boolean_or("orientation", true);
  m.roll_pitch_std_rad = s.angle_deg_or("roll_pitch_std_deg", m.roll_pitch_std_rad, {0.0, 30.0});
  m.roll_pitch_bias = bias(s, "roll_pitch_bias", "std_deg", kDegToRad, 30.0, m.roll_pitch_bias);
  m.yaw_std_rad = s.angle_deg_or("yaw_std_deg", m.yaw_std_rad, {0.0, 90.0});
  m.yaw_bias = bias(s, "yaw_bias", "std_deg", kDegToRad, 90.0, m.yaw_bias);
  m.temperature_c = s.number_or("temperature_c", m.temperature_c, {-40.0, 85.0});
}

void load_heading(const Value& s, TimeUs step_us, SensorParams& p) {
  p.heading_timing = timing(s, 10.0, step_us);
  p.heading.std_rad = s.angle_deg_or("std_deg", p.heading.std_rad, {0.0, 90.0});
  p.heading.bias = bias(s, "bias", "std_deg", kDegToRad, 90.0, p.heading.bias);
}

void load_pressure(const Value& s, TimeUs step_us, SensorParams& p) {
  p.pressure_timing = timing(s, 10.0, step_us);
  PressureModelParams& m = p.pressure;
  const std::string water = s.choice_or("water", "salt", {"fresh", "salt", "custom"});
  // water: custom needs water_density; with fresh or salt a given one is still range-checked.
  const double custom = water == "custom" ? s.number("water_density", {900.0, 1100.0})
                                          : s.number_or("water_density", 1000.0, {900.0, 1100.0});
  m.water_density = water == "fresh" ? 997.0 : water == "salt" ? 1025.0 : custom;
  m.surface_pressure_pa = s.number_or("surface_pressure_pa", 101325.0, {5e4, 1.2e5});
  m.std_pa = s.number_or("std_pa", m.std_pa, {0.0, 1e4});
  m.bias = bias(s, "bias", "std_pa", 1.0, 1e4, m.bias);
  m.depth_offset_m = s.number_or("depth_offset_m", 0.0, {-10.0, 10.0});
  m.temperature_c = s.number_or("temperature_c", m.temperature_c, {-5.0, 40.0});
}

void load_power(const Value& s, TimeUs step_us, SensorParams& p) {
  p.power_timing = timing(s, 10.0, step_us);
  BatteryModelParams& b = p.power;
  b.capacity_ah = s.number_or("capacity_ah", b.capacity_ah, {0.01, 1e4});
  b.full_v = s.number_or("full_v", b.full_v, {1.0, 100.0});
  b.empty_v = s.number_or("empty_v", b.empty_v, {0.5, 100.0});
  if (!(b.empty_v < b.full_v))
    s.at("empty_v").fail("a voltage below full_v (" + std::to_string(b.full_v) + " V)");
  b.internal_resistance_ohm =
      s.number_or("internal_resistance_ohm", b.internal_resistance_ohm, {0.0, 10.0});
  b.hotel_power_w = s.number_or("hotel_power_w", b.hotel_power_w, {0.0, 1e4});
  b.thruster_w_per_n15 = s.number_or("thruster_w_per_n15", b.thruster_w_per_n15, {0.0, 100.0});
  b.initial_consumed_ah = s.number_or("initial_consumed_ah", 0.0, {0.0, b.capacity_ah});
  b.voltage_std_v = s.number_or("voltage_std_v", b.voltage_std_v, {0.0, 10.0});
  b.current_std_a = s.number_or("current_std_a", b.current_std_a, {0.0, 100.0});
}

void load_leak(const Value& s, TimeUs step_us, SensorParams& p) {
  p.leak_timing = timing(s, 1.0, step_us);
  if (const auto probes = s.find("probes")) {
    if (!probes->is_sequence() || probes->size() == 0 || probes->size() > 32)
      probes->fail("a list of 1 to 32 probe names");
    p.leak.probes.clear();
    for (const auto& n : probes->items()) {
      const std::string name = n.as_string();
      if (name.empty() || name.size() > 15) n.fail("a probe name of 1 to 15 characters");
      p.leak.probes.push_back(name);
    }
  }
  p.leak.wet_after_s = s.number_or("wet_after_s", -1.0, {-1.0, 1e7});
}

void load_dvl(const Value& s, TimeUs step_us, SensorParams& p) {
  // Water Linked DVL-A50: velocity reports at 4-15 Hz depending on the altitude; 1..30 Hz
  // covers it and other DVLs.
  p.dvl_timing = timing(s, 8.0, step_us, false, {1.0, 30.0});
  DvlModelParams& d = p.dvl;
  d.velocity_std_m_s = s.number_or("velocity_std_m_s", d.velocity_std_m_s, {0.0, 1.0});
  if (s.has("bias_m_s")) {
    const auto b = s.numbers("bias_m_s", 3, {-1.0, 1.0});
    for (std::size_t i = 0; i < 3; ++i) d.bias_m_s[i] = b[i];
  }
  // The seabed is required when the DVL is on (what it measures depends on it).
  d.seabed_depth_m = p.dvl_timing.enabled
                         ? s.number("seabed_depth_m", {0.0, 1e3})
                         : s.number_or("seabed_depth_m", d.seabed_depth_m, {0.0, 1e3});
  d.min_altitude_m = s.number_or("min_altitude_m", d.min_altitude_m, {0.0, 100.0});
  d.max_altitude_m = s.number_or("max_altitude_m", d.max_altitude_m, {0.01, 1e3});
  if (!(d.min_altitude_m < d.max_altitude_m))
    s.at(s.has("max_altitude_m") ? "max_altitude_m" : "min_altitude_m")
        .fail("min_altitude_m < max_altitude_m (" + std::to_string(d.min_altitude_m) + " and " +
              std::to_string(d.max_altitude_m) + " m)");
  if (const auto outs = s.find("outages")) {
    if (!outs->is_sequence()) outs->fail("a list of {start_s, duration_s}");
    for (const auto& o : outs->items()) {
      const double start = o.number("start_s", {0.0, 1e7});
      const double dur = o.number("duration_s", {0.0, 1e7});
      p.dvl_outages.push_back({from_seconds(start), from_seconds(start + dur)});
    }
  }
}

}  // namespace

SensorParams load_sensor_params(const Value& root, TimeUs step_us) {
  SensorParams p;
  p.enabled = true;
  p.file = root.file();
  if (const auto s = root.find("gnss")) load_gnss(*s, root, step_us, p);
  if (const auto s = root.find("imu")) load_imu(*s, step_us, p);
  if (const auto s = root.find("heading")) load_heading(*s, step_us, p);
  if (const auto s = root.find("pressure")) load_pressure(*s, step_us, p);
  if (const auto s = root.find("power")) load_power(*s, step_us, p);
  if (const auto s = root.find("leak")) load_leak(*s, step_us, p);
  if (const auto s = root.find("dvl")) load_dvl(*s, step_us, p);
  if (root.has("datum") && !root.has("gnss")) root.at("datum").mark_used();
  return p;
}

SensorParams load_sensor_file(const std::string& path, TimeUs step_us) {
  const auto root = Value::load_file(path);
  auto p = load_sensor_params(root, step_us);
  root.check_all_used();
  return p;
}

}  // namespace tiller::sim
