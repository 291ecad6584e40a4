#include "replaytool/processes.hpp"

#include "control/control_config.hpp"
#include "control/rov_config.hpp"
#include "control/rov_node.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "esc/esc_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "mixer/mixer_node.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/channels.hpp"
#include "sim/sim_node.hpp"
#include "sim/sim_options.hpp"
#include "teleop/teleop_node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller::replaytool {

namespace ch = channels;

namespace {
// tiller-sim's options that override its config (lib/sim/sim_options.hpp, the parser tiller-sim
// itself uses), as recorded in a launch manifest. Another option is refused: replaying without
// it would compare another vehicle.
std::unique_ptr<Node> make_sim(const std::string& config, const std::vector<std::string>& args) {
  const SimOverrides o = sim_overrides(args);
  const auto root = config::Value::load_file(config);
  SimParams p = load_sim_params(root);
  root.check_all_used();
  apply(o, p);
  return std::make_unique<SimNode>(p, load_sim_vehicle_file(p.vehicle_file));
}
}  // namespace

const std::vector<ProcessEntry>& replayable_processes() {
  static const std::vector<ProcessEntry> entries = {
      // mixer and esc: no default, their config is the vehicle's (a manifest or --config).
      {"mixer",
       "",
       {ch::kThrusterCommand, ch::kAllocationStatus},
       [](const std::string& c) { return std::make_unique<MixerNode>(c); }},
      {"esc",
       "",
       {ch::kEscOutput, ch::kEscStatus, ch::kArmState},
       [](const std::string& c) { return std::make_unique<EscNode>(c); },
       {},
       /*integrating=*/false,
       // The boot nonce it drew at start (random), as its first arm state announced it.
       [](Node& n, const std::vector<Event>& log) {
         for (const Event& e : log) {
           arm_state_t a;
           if (e.channel != ch::kArmState ||
               a.decode(e.data.data(), 0, static_cast<int>(e.data.size())) < 0)
             continue;
           static_cast<EscNode&>(n).set_boot_nonce(a.boot_nonce);
           return;
         }
       }},
      {"path-follower",
       "config/guidance/default.yaml",
       {ch::kVelocitySetpoint, ch::kPathProgress, ch::kStationTarget},
       [](const std::string& c) {
         const auto root = config::Value::load_file(c);
         const auto p = guidance::load_follower_node_params(root);
         root.check_all_used();
         return std::make_unique<guidance::PathFollowerNode>(p);
       }},
      {"velocity-pid",
       "config/control/otter.yaml",
       {ch::kArbitration, ch::kWrenchVelocity, ch::kPidVelocity},
       [](const std::string& c) {
         return std::make_unique<control::VelocityPidNode>(
             control::load_velocity_pid_node_params(config::Value::load_file(c)));
       },
       {},
       /*integrating=*/true},
      {"station-keep",
       "config/control/otter.yaml",
       {ch::kWrenchStation, ch::kPidStation},
       [](const std::string& c) {
         return std::make_unique<control::StationKeepNode>(
             control::load_station_keep_node_params(config::Value::load_file(c)));
       },
       {},
       /*integrating=*/true},
      {"rov-control",
       "config/control/bluerov2.yaml",
       // Not TILLER_MODE: its position-loss fallback shares the channel with the mission's and
       // the pilot's requests, so a log cannot say which are its own.
       {ch::kArbitration, ch::kWrenchRov},
       [](const std::string& c) {
         return std::make_unique<control::RovControlNode>(control::load_rov_control_file(c));
       },
       {},
       /*integrating=*/true},
      {"teleop",
       "config/teleop/gamepad_xbox.yaml",
       {ch::kManualDemand, ch::kManualVelocity},
       [](const std::string& c) {
         return std::make_unique<TeleopNode>(load_teleop_file(c), TeleopNode::Input::replay);
       }},
      // The estimator: a Kalman filter integrates every input, so a live log is shown, not
      // judged; a lockstep log (tiller-run --odometry estimated) must match bit for bit.
      {"nav",
       "config/nav/usv.yaml",
       {ch::kOdometry},
       [](const std::string& c) { return std::make_unique<nav::NavNode>(nav::load_nav_file(c)); },
       {},
       /*integrating=*/true},
      {"sim",
       "config/sim/sim.yaml",
       {ch::kOdometry, ch::kGroundTruth, ch::kSimState},
       [](const std::string& c) { return std::make_unique<SimNode>(c); },
       make_sim,
       /*integrating=*/true},
  };
  return entries;
}

}  // namespace tiller::replaytool
