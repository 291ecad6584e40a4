// tiller-sim: the simulated vehicle, the default vehicle when no hardware is attached.
// Subscribes TILLER_ESC_OUTPUT; publishes TILLER_ODOMETRY, TILLER_GROUND_TRUTH and
// TILLER_SIM_STATE in real time. See lib/sim/sim_node.hpp and config/sim/sim.yaml.
//
// Flags override the config and are checked as strictly as it is: the whole string must be a
// finite number (an integer for --seed) within the range load_sim_params accepts for the same
// setting; otherwise the program exits 2 naming the flag, the expected range and the value.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/angles.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sim/sim_node.hpp"

namespace {
std::string fmt(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}

// The flag's value as a finite number in [lo, hi] (the same range as the config key).
double number(const tiller::app::Args& a, const std::string& name, double lo, double hi,
              const char* unit) {
  return tiller::app::number_option(
      a, name, lo, hi, "a finite number in [" + fmt(lo) + ", " + fmt(hi) + "] " + unit);
}
}  // namespace

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args =
      app::parse(argc, argv,
                 {"tiller-sim",
                  "Simulated vehicle (Fossen model): ESC output in, odometry and ground truth out.",
                  "sim/sim.yaml",
                  {{"vehicle", "FILE", "vehicle file (overrides the config's vehicle:)", ""},
                   {"seed", "N", "seed of the current and the odometry noise (integer >= 0)", ""},
                   {"north", "M", "initial north position (-1e6..1e6)", ""},
                   {"east", "M", "initial east position (-1e6..1e6)", ""},
                   {"heading-deg", "DEG", "initial heading (-360..360)", ""},
                   {"current-speed", "M_S",
                    "constant current speed, 0..5 (towards north unless --current-toward-deg)", ""},
                   {"current-toward-deg", "DEG",
                    "direction the constant current flows towards (0 = north, -360..360); needs "
                    "--current-speed",
                    ""}}});
  return app::guarded_main("tiller-sim", [&] {
    // Flags first: a bad one is refused before any file is read or LCM is opened.
    const bool has_speed = !args.get("current-speed").empty();
    const bool has_toward = !args.get("current-toward-deg").empty();
    if (has_toward && !has_speed)
      throw std::runtime_error(
          "--current-toward-deg: expected together with --current-speed (the speed of the "
          "constant current), got '" +
          args.get("current-toward-deg") + "' alone");
    const auto given = [&](const char* n) { return !args.get(n).empty(); };
    const double north = given("north") ? number(args, "north", -1e6, 1e6, "m") : 0;
    const double east = given("east") ? number(args, "east", -1e6, 1e6, "m") : 0;
    const double heading = given("heading-deg") ? number(args, "heading-deg", -360, 360, "deg") : 0;
    const double speed = has_speed ? number(args, "current-speed", 0, 5, "m/s") : 0;
    const double toward = has_toward ? number(args, "current-toward-deg", -360, 360, "deg") : 0;
    const auto s = given("seed")
                       ? static_cast<std::uint64_t>(app::integer_option(
                             args, "seed", 0, INT64_MAX, "an integer in [0, 9223372036854775807]"))
                       : std::uint64_t{0};

    const auto root = config::Value::load_file(args.config);  // resolved by app::parse
    SimParams p = load_sim_params(root);
    root.check_all_used();
    if (given("vehicle")) p.vehicle_file = app::resolve_path(args.get("vehicle"));
    if (given("seed")) p.seed = s;
    if (given("north")) p.initial_eta[0] = north;
    if (given("east")) p.initial_eta[1] = east;
    if (given("heading-deg")) p.initial_eta[5] = wrap_pi(deg_to_rad(heading));
    if (has_speed) {
      p.current.model = sim::CurrentParams::Model::kConstant;
      p.current.speed_m_s = speed;
      p.current.speed_max_m_s = speed;
      p.current.toward_rad = wrap_pi(deg_to_rad(toward));
    }
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    std::fprintf(stderr, "tiller-sim: %s (%s), %zu thrusters, step %.1f ms, odometry %.0f Hz\n",
                 node.vehicle().name.c_str(), p.vehicle_file.c_str(),
                 node.vehicle().thrusters.size(), to_seconds(p.step_us) * 1e3,
                 1.0 / to_seconds(p.odometry_period_us));
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
