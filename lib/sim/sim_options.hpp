// tiller-sim's command-line overrides of its config, parsed, checked and applied in one place so
// that tiller-sim, tiller-replay (a sim entry recorded in a launch manifest) and tiller-run
// start the same simulated vehicle from the same options:
//   --vehicle FILE                 the vehicle file (instead of the config's vehicle:)
//   --seed N                       the current's and the odometry noise's seed
//   --mission FILE                 start where the mission file's `start:` says (north, east and,
//                                  when given, heading); the flags below win over it; a mission
//                                  without start: (a CSV one) leaves the config's pose
//   --north M --east M --heading-deg DEG       the initial pose (NED m, deg)
//   --current-speed M_S [--current-toward-deg DEG]   a constant current (replaces the config's)
//   --sensors FILE|none            the simulated sensors (config/sim/sensors/*.yaml; none: off)
//   --odometry truth|estimated     TILLER_ODOMETRY from the model, or none (tiller-nav's job)
//   --gnss-output lcm|nmea|both    TILLER_GNSS from the simulator and/or NMEA for gpsd
//   --gnss-outage START_S:DURATION_S   no GNSS fix for that long (s after the start; repeatable
//                                  as a comma list: 40:20,90:5)
//   --dvl-outage START_S:DURATION_S    no dvl_t at all for that long (a comma list, as above)
//   --force-step AT_S:N,E,D        from AT_S s after the start on, an outside force of N, E, D
//                                  newtons (NED) on the vehicle (underwater_6dof only)
//   --leak-at S                    every leak probe turns wet S seconds after the start
//   --battery-used-ah AH           the battery starts with AH already drawn
//   --mass-scale S --damping-scale S   the vehicle's mass (with added mass and inertia) and its
//                                  damping times S (0.1..10): a vehicle the gains were not tuned on
//   --nmea-link PATH               (tiller-sim) a symlink to the NMEA pseudo-terminal
// Numbers are checked as strictly as the config: the whole string a finite number within the
// range load_sim_params accepts, else "--NAME: expected E, got 'V'" (std::runtime_error; the
// programs exit 2 with it).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "runtime/app.hpp"
#include "sim/sim_node.hpp"

namespace tiller {

struct SimOverrides {
  std::optional<std::string> vehicle_file;
  std::optional<std::uint64_t> seed;
  std::optional<double> north, east;        // m
  std::optional<double> heading;            // rad, wrapped to (-pi, pi]
  std::optional<double> current_speed;      // m/s: a constant current
  double current_toward = 0;                // rad, wrapped: where the water flows towards
  std::string mission_file;                 // where the start came from ("" none)
  std::optional<std::string> sensors_file;  // "none": no sensors
  std::optional<bool> publish_odometry;
  std::optional<std::string> gnss_output;  // lcm | nmea | both
  std::vector<sim::GnssOutage> gnss_outages;
  std::vector<sim::DvlOutage> dvl_outages;
  std::optional<SimParams::ForceStep> force_step;
  std::optional<double> leak_at_s, battery_used_ah;
  std::optional<double> mass_scale, damping_scale;
  std::string nmea_link;  // tiller-sim only (the pseudo-terminal is I/O, not the node's)
};

// The options above as tiller-sim declares them (their --help lines).
std::vector<app::Option> sim_options();

// Reads and checks the options present in `a` (a --mission file that cannot be read is refused
// naming it; the mission's start fills only what the flags leave unset).
SimOverrides sim_overrides(const app::Args& a);

// The same from a recorded argument list ("--north", "5", "--mission=FILE", ...), for replay;
// `resolve` maps a recorded relative path. An option tiller-sim does not take is refused.
SimOverrides sim_overrides(const std::vector<std::string>& args,
                           std::string (*resolve)(const std::string&) = nullptr);

// Applies them on top of a loaded config.
void apply(const SimOverrides& o, SimParams& p);

}  // namespace tiller
