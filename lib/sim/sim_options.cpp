#include "sim/sim_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

#include "core/angles.hpp"
#include "mission/mission.hpp"

namespace tiller {

namespace {
std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}

// The option's value as a finite number in [lo, hi] (the same range as the config key).
double number(const app::Args& a, const std::string& name, double lo, double hi, const char* unit) {
  return app::number_option(a, name, lo, hi,
                            "a finite number in [" + fmt(lo) + ", " + fmt(hi) + "] " + unit);
}
// "40:20,90:5" -> [40, 60) s and [90, 95) s.
std::vector<sim::GnssOutage> parse_outages(const std::string& text, const char* flag) {
  std::vector<sim::GnssOutage> out;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string item = text.substr(at, comma - at);
    const std::size_t colon = item.find(':');
    double start = 0, dur = 0;
    std::size_t n1 = 0, n2 = 0;
    bool ok = colon != std::string::npos;
    try {
      if (ok) {
        start = std::stod(item.substr(0, colon), &n1);
        dur = std::stod(item.substr(colon + 1), &n2);
      }
    } catch (const std::exception&) {
      ok = false;
    }
    ok = ok && n1 == colon && n2 == item.size() - colon - 1 && std::isfinite(start) &&
         std::isfinite(dur) && start >= 0 && dur > 0 && start <= 1e7 && dur <= 1e7;
    if (!ok)
      throw std::runtime_error(
          std::string("--") + flag +
          ": expected START_S:DURATION_S (start >= 0, duration > 0, s; a comma list for "
          "several, e.g. 40:20,90:5), got '" +
          text + "'");
    out.push_back({from_seconds(start), from_seconds(start + dur)});
    at = comma + 1;
  }
  return out;
}

// "30:0,20,0" -> from 30 s on, 20 N east. Every part a whole finite number: AT_S in [0, 1e7],
// each force in [-1e4, 1e4] N.
SimParams::ForceStep parse_force_step(const std::string& text) {
  SimParams::ForceStep f;
  bool ok = true;
  const std::size_t colon = text.find(':');
  double v[4] = {};
  if (colon == std::string::npos) ok = false;
  std::size_t at = 0;
  for (int i = 0; ok && i < 4; ++i) {
    const std::size_t end = i == 0 ? colon : i < 3 ? text.find(',', at) : text.size();
    if (end == std::string::npos || end <= at) {
      ok = false;
      break;
    }
    const std::string part = text.substr(at, end - at);
    if (part.find_first_of(" \t") != std::string::npos) {
      ok = false;
      break;
    }
    std::size_t n = 0;
    try {
      v[i] = std::stod(part, &n);
    } catch (const std::exception&) {
      ok = false;
      break;
    }
    const double lim = i == 0 ? 1e7 : 1e4;
    ok = n == part.size() && std::isfinite(v[i]) && v[i] >= (i == 0 ? 0.0 : -lim) && v[i] <= lim;
    at = end + 1;
  }
  if (ok && text.find(':', colon + 1) != std::string::npos) ok = false;
  if (!ok)
    throw std::runtime_error(
        "--force-step: expected AT_S:N,E,D (from AT_S s after the start on, in [0, 1e7], a force "
        "of N, E, D newtons in NED, each in [-1e4, 1e4], e.g. 30:0,20,0), got '" +
        text + "'");
  f.enabled = true;
  f.at_us = from_seconds(v[0]);
  f.force_ned = sim::Vector3(v[1], v[2], v[3]);
  return f;
}

}  // namespace

std::vector<app::Option> sim_options() {
  return {
      {"vehicle", "FILE", "vehicle file (overrides the config's vehicle:)", ""},
      {"seed", "N", "seed of the current and the odometry noise (integer >= 0)", ""},
      {"mission", "FILE",
       "start where this mission file's start: says (the flags below win over it)", ""},
      {"north", "M", "initial north position (-1e6..1e6)", ""},
      {"east", "M", "initial east position (-1e6..1e6)", ""},
      {"heading-deg", "DEG", "initial heading (-360..360)", ""},
      {"current-speed", "M_S",
       "constant current speed, 0..5 (towards north unless --current-toward-deg)", ""},
      {"current-toward-deg", "DEG",
       "direction the constant current flows towards (0 = north, -360..360); needs "
       "--current-speed",
       ""},
      {"sensors", "FILE",
       "simulated sensors file (config/sim/sensors/usv.yaml, ...), or none (overrides the "
       "config's sensors:)",
       ""},
      {"odometry", "MODE",
       "truth: publish TILLER_ODOMETRY from the model; estimated: publish none (tiller-nav "
       "estimates it from the simulated sensors)",
       ""},
      {"gnss-output", "WHERE",
       "lcm: TILLER_GNSS from the simulator; nmea: NMEA to the pseudo-terminal (gpsd, "
       "tiller-gnss); both",
       ""},
      {"gnss-outage", "START:DURATION",
       "no GNSS fix from START s after the start for DURATION s (a comma list for several)", ""},
      {"dvl-outage", "START:DURATION",
       "no TILLER_DVL at all from START s after the start for DURATION s (a comma list for "
       "several; needs a sensors file with dvl: enabled)",
       ""},
      {"force-step", "AT_S:N,E,D",
       "from AT_S s after the start on, hold an outside force of N,E,D newtons (NED) on the "
       "vehicle (underwater_6dof only; replaces the config's disturbance.force_step)",
       ""},
      {"leak-at", "S", "every leak probe turns wet S s after the start (0..1e7)", ""},
      {"battery-used-ah", "AH", "the battery starts with AH already drawn (0..capacity)", ""},
      {"mass-scale", "S",
       "the vehicle's mass, added mass and inertia times S (0.1..10; tiller-tune's unseen vehicle)",
       ""},
      {"damping-scale", "S",
       "the vehicle's linear, quadratic and cross-flow damping times S (0.1..10)", ""},
      {"nmea-link", "PATH",
       "make PATH a symlink to the NMEA pseudo-terminal (for gpsd; needs nmea output)", ""}};
}

SimOverrides sim_overrides(const app::Args& a) {
  SimOverrides o;
  const auto given = [&](const char* n) { return !a.get(n).empty(); };
  if (given("current-toward-deg") && !given("current-speed"))
    throw std::runtime_error(
        "--current-toward-deg: expected together with --current-speed (the speed of the "
        "constant current), got '" +
        a.get("current-toward-deg") + "' alone");
  if (given("north")) o.north = number(a, "north", -1e6, 1e6, "m");
  if (given("east")) o.east = number(a, "east", -1e6, 1e6, "m");
  if (given("heading-deg"))
    o.heading = wrap_pi(deg_to_rad(number(a, "heading-deg", -360, 360, "deg")));
  if (given("current-speed")) o.current_speed = number(a, "current-speed", 0, 5, "m/s");
  if (given("current-toward-deg"))
    o.current_toward = wrap_pi(deg_to_rad(number(a, "current-toward-deg", -360, 360, "deg")));
  if (given("seed"))
    o.seed = static_cast<std::uint64_t>(
        app::integer_option(a, "seed", 0, INT64_MAX, "an integer in [0, 9223372036854775807]"));
  if (given("vehicle")) o.vehicle_file = app::resolve_path(a.get("vehicle"));
  if (given("sensors"))
    o.sensors_file = a.get("sensors") == "none" ? "none" : app::resolve_path(a.get("sensors"));
  if (given("odometry")) {
    const std::string m = a.get("odometry");
    if (m != "truth" && m != "estimated")
      throw std::runtime_error("--odometry: expected truth or estimated, got '" + m + "'");
    o.publish_odometry = m == "truth";
  }
  if (given("gnss-output")) {
    const std::string m = a.get("gnss-output");
    if (m != "lcm" && m != "nmea" && m != "both")
      throw std::runtime_error("--gnss-output: expected lcm, nmea or both, got '" + m + "'");
    o.gnss_output = m;
  }
  if (given("gnss-outage")) o.gnss_outages = parse_outages(a.get("gnss-outage"), "gnss-outage");
  if (given("dvl-outage")) o.dvl_outages = parse_outages(a.get("dvl-outage"), "dvl-outage");
  if (given("force-step")) o.force_step = parse_force_step(a.get("force-step"));
  if (given("leak-at")) o.leak_at_s = number(a, "leak-at", 0, 1e7, "s");
  if (given("battery-used-ah")) o.battery_used_ah = number(a, "battery-used-ah", 0, 1e4, "Ah");
  if (given("mass-scale")) o.mass_scale = number(a, "mass-scale", 0.1, 10, "(a factor)");
  if (given("damping-scale")) o.damping_scale = number(a, "damping-scale", 0.1, 10, "(a factor)");
  o.nmea_link = a.get("nmea-link");
  if (given("mission")) {
    o.mission_file = app::resolve_path(a.get("mission"));
    const auto m = mission::load_mission_file(o.mission_file);
    // Without start: (a CSV mission, or a YAML one without the key) the config's pose stays.
    if (m.start) {
      if (!o.north) o.north = m.start->north;
      if (!o.east) o.east = m.start->east;
      if (!o.heading && m.start->has_heading) o.heading = m.start->heading;
    }
  }
  return o;
}

SimOverrides sim_overrides(const std::vector<std::string>& args,
                           std::string (*resolve)(const std::string&)) {
  app::Args a;
  const auto opts = sim_options();
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string key = args[i], value;
    if (key.rfind("--", 0) != 0) continue;
    if (const auto eq = key.find('='); eq != std::string::npos) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    } else if (i + 1 < args.size()) {
      value = args[++i];
    }
    const std::string name = key.substr(2);
    if (name == "config" || name == "lcm-url") continue;
    bool known = false;
    for (const auto& op : opts) known |= op.name == name;
    if (!known)
      throw std::invalid_argument("sim: replay cannot apply the recorded option " + key +
                                  " (tiller-sim does not take it)");
    if (resolve &&
        (name == "vehicle" || name == "mission" || (name == "sensors" && value != "none")))
      value = resolve(value);
    a.values[name] = value;
  }
  return sim_overrides(a);
}

void apply(const SimOverrides& o, SimParams& p) {
  if (o.vehicle_file) p.vehicle_file = *o.vehicle_file;
  if (o.seed) p.seed = *o.seed;
  if (o.north) p.initial_eta[0] = *o.north;
  if (o.east) p.initial_eta[1] = *o.east;
  if (o.heading) p.initial_eta[5] = *o.heading;
  if (o.current_speed) {
    p.current.model = sim::CurrentParams::Model::kConstant;
    p.current.speed_m_s = *o.current_speed;
    p.current.speed_max_m_s = *o.current_speed;
    p.current.toward_rad = o.current_toward;
  }
  if (o.publish_odometry) p.publish_odometry = *o.publish_odometry;
  if (o.sensors_file) {
    p.sensors = *o.sensors_file == "none" ? sim::SensorParams{}
                                          : sim::load_sensor_file(*o.sensors_file, p.step_us);
  }
  auto need_sensors = [&](const char* flag) {
    if (!p.sensors.enabled)
      throw std::runtime_error(std::string("--") + flag +
                               ": expected simulated sensors (--sensors FILE, or the config's "
                               "sensors:), but there are none");
  };
  if (o.gnss_output) {
    need_sensors("gnss-output");
    p.sensors.gnss_lcm = *o.gnss_output != "nmea";
    p.sensors.gnss_nmea = *o.gnss_output != "lcm";
  }
  if (!o.gnss_outages.empty()) {
    need_sensors("gnss-outage");
    p.sensors.gnss_outages.insert(p.sensors.gnss_outages.end(), o.gnss_outages.begin(),
                                  o.gnss_outages.end());
  }
  if (!o.dvl_outages.empty()) {
    need_sensors("dvl-outage");
    if (!p.sensors.dvl_timing.enabled)
      throw std::runtime_error("--dvl-outage: expected the sensors file (" + p.sensors.file +
                               ") to enable dvl:, but it does not");
    p.sensors.dvl_outages.insert(p.sensors.dvl_outages.end(), o.dvl_outages.begin(),
                                 o.dvl_outages.end());
  }
  if (o.force_step) {
    p.force_step = *o.force_step;
    p.force_step_key = "--force-step";
  }
  if (o.leak_at_s) {
    need_sensors("leak-at");
    p.sensors.leak.wet_after_s = *o.leak_at_s;
    if (!p.sensors.leak_timing.enabled)
      throw std::runtime_error("--leak-at: expected the sensors file (" + p.sensors.file +
                               ") to enable leak:, but it does not");
  }
  if (o.battery_used_ah) {
    need_sensors("battery-used-ah");
    if (*o.battery_used_ah > p.sensors.power.capacity_ah)
      throw std::runtime_error("--battery-used-ah: expected at most the capacity, " +
                               fmt(p.sensors.power.capacity_ah) + " Ah (" + p.sensors.file +
                               "), got '" + fmt(*o.battery_used_ah) + "'");
    p.sensors.power.initial_consumed_ah = *o.battery_used_ah;
  }
  if (o.mass_scale) p.mass_scale = *o.mass_scale;
  if (o.damping_scale) p.damping_scale = *o.damping_scale;
  if (!o.nmea_link.empty() && !p.sensors.gnss_nmea)
    throw std::runtime_error(
        "--nmea-link: expected NMEA output (--gnss-output nmea or both, or gnss.output in the "
        "sensors file), got '" +
        o.nmea_link + "' with " + (p.sensors.enabled ? "output lcm" : "no sensors"));
}

}  // namespace tiller
