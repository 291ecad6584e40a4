#include "sim/sim_options.hpp"

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
}  // namespace

std::vector<app::Option> sim_options() {
  return {{"vehicle", "FILE", "vehicle file (overrides the config's vehicle:)", ""},
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
           ""}};
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
    if (resolve && (name == "vehicle" || name == "mission")) value = resolve(value);
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
}

}  // namespace tiller
