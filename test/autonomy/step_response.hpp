// Velocity PID step response in closed loop (manual closed-loop mode, a constant command on one
// axis: surge u, sway v (m/s) or yaw rate r (rad/s), zero on the others), run in lockstep with a
// plant. Returns that axis' samples and overshoot / settling.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "runtime/node.hpp"

namespace tiller::test {

enum class StepAxis { kSurge = 0, kSway = 1, kYawRate = 5 };  // odometry velocity index

struct StepResult {
  double final_speed = 0;  // m/s (rad/s for yaw rate), mean over the last 2 s
  double peak = 0;         // m/s
  double overshoot = 0;    // fraction of the step
  double rise_s = -1;      // s to 90 %
  double settle_s = -1;    // s after which the speed stays within 5 % of the command
  std::vector<double> t, u;
};

// `plant` must publish TILLER_ODOMETRY and follow TILLER_ARBITRATION / TILLER_WRENCH_VELOCITY.
StepResult velocity_step(const std::string& control_file, double command,
                         std::vector<std::unique_ptr<Node>> plant, double duration_s = 15,
                         StepAxis axis = StepAxis::kSurge);

}  // namespace tiller::test
