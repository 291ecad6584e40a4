// tiller-sim: the simulated vehicle, the default vehicle when no hardware is attached.
// Subscribes TILLER_ESC_OUTPUT; publishes TILLER_ODOMETRY, TILLER_GROUND_TRUTH and
// TILLER_SIM_STATE in real time. See lib/sim/sim_node.hpp and config/sim/sim.yaml.
//
// Flags override the config (lib/sim/sim_options.hpp: the same parser tiller-replay and
// tiller-run use) and are checked as strictly as it is: the whole string must be a finite number
// (an integer for --seed) within the range load_sim_params accepts for the same setting;
// otherwise the program exits 2 naming the flag, the expected range and the value.
// --mission FILE starts the vehicle at the mission's start: pose (the launch files pass the
// mission they fly), so a simulated run starts where the mission file says.
// With simulated sensors whose GNSS output includes NMEA (--gnss-output nmea|both) it opens a
// pseudo-terminal for gpsd (lib/sim/nmea_pty.hpp), prints its path, and with --nmea-link PATH
// makes PATH a symlink to it.
#include <cstdio>
#include <memory>
#include <string>

#include "core/angles.hpp"

#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sim/nmea_pty.hpp"
#include "sim/sim_node.hpp"
#include "sim/sim_options.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args =
      app::parse(argc, argv,
                 {"tiller-sim",
                  "Simulated vehicle (Fossen model): ESC output in, odometry and ground truth out.",
                  "sim/sim.yaml", sim_options()});
  return app::guarded_main("tiller-sim", [&] {
    // Flags first: a bad one is refused before any config is read or LCM is opened.
    const SimOverrides o = sim_overrides(args);
    const auto root = config::Value::load_file(args.config);  // resolved by app::parse
    SimParams p = load_sim_params(root);
    root.check_all_used();
    apply(o, p);
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    const std::string from = o.mission_file.empty() ? "" : " (from " + o.mission_file + ")";
    std::fprintf(stderr,
                 "tiller-sim: %s (%s), %zu thrusters, step %.1f ms, odometry %.0f Hz; starts at "
                 "north %.2f m, east %.2f m, heading %.1f deg%s\n",
                 node.vehicle().name.c_str(), p.vehicle_file.c_str(),
                 node.vehicle().thrusters.size(), to_seconds(p.step_us) * 1e3,
                 1.0 / to_seconds(p.odometry_period_us), p.initial_eta[0], p.initial_eta[1],
                 rad_to_deg(p.initial_eta[5]), from.c_str());
    if (p.sensors.enabled)
      std::fprintf(stderr, "tiller-sim: simulated sensors from %s; odometry: %s\n",
                   p.sensors.file.c_str(), p.publish_odometry ? "truth" : "estimated (none)");
    if (p.sensors.enabled && p.sensors.dvl_timing.enabled)
      std::fprintf(stderr,
                   "tiller-sim: DVL on TILLER_DVL at %.1f Hz, seabed at %.1f m, %zu outages\n",
                   1.0 / to_seconds(p.sensors.dvl_timing.period_us), p.sensors.dvl.seabed_depth_m,
                   p.sensors.dvl_outages.size());
    if (p.force_step.enabled)
      std::fprintf(stderr,
                   "tiller-sim: a step force of [%.2f %.2f %.2f] N (NED) from %.2f s after the "
                   "start (%s)\n",
                   p.force_step.force_ned.x(), p.force_step.force_ned.y(),
                   p.force_step.force_ned.z(), to_seconds(p.force_step.at_us),
                   p.force_step_key.c_str());
    std::unique_ptr<sim::NmeaPty> pty;
    if (p.sensors.enabled && p.sensors.gnss_nmea && p.sensors.gnss_timing.enabled) {
      pty = std::make_unique<sim::NmeaPty>(o.nmea_link);
      node.set_nmea_sink(pty.get());
      std::fprintf(stderr, "tiller-sim: NMEA (GGA, GSA, GSV, GST, RMC) on %s%s%s\n",
                   pty->slave_path().c_str(), o.nmea_link.empty() ? "" : ", linked from ",
                   o.nmea_link.c_str());
    }
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
