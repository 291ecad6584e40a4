// Closed-loop mission runs for tests and the benchmark: the autonomy nodes (path follower,
// velocity PID with the arbiter, station keep, mission publisher) and a plant, in one
// LockstepExecutor on simulated time. Collects the pose, progress, arbitration switches and
// the active wrench, and scores the run (lib/scores).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "guidance/follower_config.hpp"
#include "mission/mission.hpp"
#include "runtime/node.hpp"
#include "scores/path_metrics.hpp"
#include "scores/scores.hpp"

namespace tiller::test {

struct RunConfig {
  std::string guidance_file = "config/guidance/default.yaml";  // relative to the source tree
  std::string control_file = "config/control/otter.yaml";
  std::string mission_file = "config/missions/default.yaml";
  double current_speed = 0.3;    // m/s
  double current_from_deg = 30;  // deg, where the water comes from
  double hold_s = -1;            // station keeping after completion; < 0: the mission's
  double time_limit_s = -1;      // s of simulated time; < 0: the mission's time_limit_s
  // Builds the plant nodes (added to the executor before the controllers). Default: SimplePlant.
  std::function<std::vector<std::unique_ptr<Node>>(const mission::Mission&, double current_speed,
                                                   double current_from_rad)>
      make_plant;
  std::string pose_channel = "TILLER_ODOMETRY";  // ground truth when the plant has it
  // Changes the follower's parameters after loading (benchmark variants).
  std::function<void(guidance::FollowerNodeParams&)> tweak_follower;
};

struct RunResult {
  mission::Mission mission;
  scores::PathScores path;
  bool completed = false;
  double completed_at = -1;         // s
  int skipped = 0;                  // follower's count of points passed outside the radius
  double station_vrx = -1;          // VRX station-keeping score over the hold
  double station_max_distance = 0;  // m, over the hold
  double held_s = 0;                // s of station keeping after completion
  int switches = 0;                 // arbitration changes
  double max_switch_jump = 0;       // N: largest step of the active X/Y force between two
                                    // wrenches within 2 s after a hand-over between the
                                    // velocity PID and station keeping
  double max_force = 0;             // N: largest active |X|
  double max_setpoint_speed = 0;    // m/s: largest |velocity| of an active NED setpoint
  scores::CornerScores corners;     // steady cross-track and corner overshoot
  double sim_s = 0, wall_s = 0;
  std::vector<scores::Pose> poses;
};

RunResult run_mission(const RunConfig& c);

std::string source_path(const std::string& rel);

}  // namespace tiller::test
