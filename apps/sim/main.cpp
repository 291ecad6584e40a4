// tiller-sim: the simulated vehicle, the default vehicle when no hardware is attached.
// Subscribes TILLER_ESC_OUTPUT; publishes TILLER_ODOMETRY, TILLER_GROUND_TRUTH and
// TILLER_SIM_STATE in real time. See lib/sim/sim_node.hpp and config/sim/sim.yaml.
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/angles.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sim/sim_node.hpp"

namespace {
// A relative path that does not exist from here is looked up in the source tree.
std::string resolve(const std::string& p) {
  if (p.empty() || std::filesystem::exists(p) || std::filesystem::path(p).is_absolute()) return p;
  for (const char* base : {TILLER_SOURCE_DIR "/config/", TILLER_SOURCE_DIR "/"}) {
    if (std::filesystem::exists(base + p)) return base + p;
  }
  return p;
}
double number(const tiller::app::Args& a, const std::string& name) {
  try {
    return std::stod(a.get(name));
  } catch (const std::exception&) {
    throw std::runtime_error("--" + name + ": expected a number, got '" + a.get(name) + "'");
  }
}
}  // namespace

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(
      argc, argv,
      {"tiller-sim",
       "Simulated vehicle (Fossen model): ESC output in, odometry and ground truth out.",
       "sim/sim.yaml",
       {{"vehicle", "FILE", "vehicle file (overrides the config's vehicle:)", ""},
        {"seed", "N", "seed of the current and the odometry noise", ""},
        {"north", "M", "initial north position", ""},
        {"east", "M", "initial east position", ""},
        {"heading-deg", "DEG", "initial heading", ""},
        {"current-speed", "M_S", "constant current speed (with --current-toward-deg)", ""},
        {"current-toward-deg", "DEG", "direction the constant current flows towards (0 = north)",
         ""}}});
  return app::guarded_main("tiller-sim", [&] {
    const std::string config_path = resolve(args.config);
    const auto root = config::Value::load_file(config_path);
    SimParams p = load_sim_params(root);
    root.check_all_used();
    if (!args.get("vehicle").empty()) p.vehicle_file = resolve(args.get("vehicle"));
    if (!args.get("seed").empty()) p.seed = static_cast<std::uint64_t>(number(args, "seed"));
    if (!args.get("north").empty()) p.initial_eta[0] = number(args, "north");
    if (!args.get("east").empty()) p.initial_eta[1] = number(args, "east");
    if (!args.get("heading-deg").empty())
      p.initial_eta[5] = wrap_pi(deg_to_rad(number(args, "heading-deg")));
    if (!args.get("current-speed").empty()) {
      p.current.model = sim::CurrentParams::Model::kConstant;
      p.current.speed_m_s = number(args, "current-speed");
      p.current.speed_max_m_s = p.current.speed_m_s;
      const bool toward = !args.get("current-toward-deg").empty();
      p.current.toward_rad = toward ? wrap_pi(deg_to_rad(number(args, "current-toward-deg"))) : 0.0;
    }
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    std::fprintf(stderr, "tiller-sim: %s (%s), %zu thrusters, step %.1f ms, odometry %.0f Hz\n",
                 node.vehicle().name.c_str(), p.vehicle_file.c_str(),
                 node.vehicle().thrusters.size(), to_seconds(p.step_us) * 1e3,
                 1.0 / to_seconds(p.odometry_period_us));
    LiveExecutor ex(args.lcm_url);
    ex.add(node);
    return ex.run();
  });
}
