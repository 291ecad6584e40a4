#include "processes.hpp"

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "esc/esc_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "sim/sim_node.hpp"
#include "teleop/teleop_node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller::replaytool {

namespace ch = channels;

const std::vector<ProcessEntry>& replayable_processes() {
  static const std::vector<ProcessEntry> entries = {
      {"mixer",
       "config/mixer/seed001_rov6.yaml",
       {ch::kThrusterCommand, ch::kAllocationStatus},
       [](const std::string& c) { return std::make_unique<MixerNode>(c); }},
      {"esc",
       "config/esc/sim.yaml",
       {ch::kEscOutput, ch::kEscStatus, ch::kArmState},
       [](const std::string& c) { return std::make_unique<EscNode>(c); }},
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
       }},
      {"station-keep",
       "config/control/otter.yaml",
       {ch::kWrenchStation, ch::kPidStation},
       [](const std::string& c) {
         return std::make_unique<control::StationKeepNode>(
             control::load_station_keep_node_params(config::Value::load_file(c)));
       }},
      {"teleop",
       "config/teleop/gamepad_xbox.yaml",
       {ch::kManualDemand, ch::kManualVelocity},
       [](const std::string& c) {
         return std::make_unique<TeleopNode>(load_teleop_file(c), TeleopNode::Input::replay);
       }},
      {"sim",
       "config/sim/sim.yaml",
       {ch::kOdometry, ch::kGroundTruth, ch::kSimState},
       [](const std::string& c) { return std::make_unique<SimNode>(c); }},
  };
  return entries;
}

}  // namespace tiller::replaytool
