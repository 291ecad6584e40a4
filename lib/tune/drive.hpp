// tiller-tune's manoeuvres in the simulator: a stick script (config/pilot/tune_*.yaml, the same
// file tiller-stick-script plays on the water) flown through the real pilot path -- the scripted
// stick into TeleopNode (as the device would give it: arming from the stick's button after it
// was centred, the preset's deadzone, expo and gain), MixerNode, EscNode (sim backend) -- on
// SimNode, in lockstep (simulated time, bit for bit). The vehicle can be one the gains were not
// tuned on (sim_args "--mass-scale 1.3 --damping-scale 1.5"). Returns the messages
// record_from_events() reads and, when asked, writes the whole run as an LCM log.
#pragma once

#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::tune {

struct DriveSpec {
  std::string vehicle_file = "config/vehicles/otter.yaml";
  std::string script_file = "config/pilot/tune_usv.yaml";
  std::string teleop_file = "config/teleop/gamepad_blueboat.yaml";
  std::string sim_file = "config/sim/sim.yaml";
  // Empty: config/esc/<vehicle>_sim.yaml, config/mixer/<vehicle>.yaml (as tiller-run).
  std::string esc_file, mixer_file;
  std::vector<std::string> sim_args;  // tiller-sim options ("--mass-scale", "1.3", ...)
  double time_limit_s = 600;
  std::string log_file;  // empty: no log
};

struct DriveOutcome {
  bool done = false;          // the script ran to its end
  std::string why;            // the script failed: why
  double sim_s = 0;           // simulated seconds
  std::vector<Event> events;  // TILLER_GROUND_TRUTH, TILLER_ODOMETRY, TILLER_ESC_OUTPUT
  std::string vehicle_file, esc_file, mixer_file;  // resolved
};

// Config errors throw config::Error; a missing file std::runtime_error naming it.
DriveOutcome drive(const DriveSpec& spec);

}  // namespace tiller::tune
