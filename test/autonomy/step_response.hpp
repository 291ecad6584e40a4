// Velocity PID step response in closed loop (manual closed-loop mode, constant surge command),
// run in lockstep with a plant. Returns the surge speed samples and overshoot / settling.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "runtime/node.hpp"

namespace tiller::test {

struct StepResult {
  double final_speed = 0;  // m/s, mean over the last 2 s
  double peak = 0;         // m/s
  double overshoot = 0;    // fraction of the step
  double rise_s = -1;      // s to 90 %
  double settle_s = -1;    // s after which the speed stays within 5 % of the command
  std::vector<double> t, u;
};

// `plant` must publish TILLER_ODOMETRY and follow TILLER_ARBITRATION / TILLER_WRENCH_VELOCITY.
StepResult velocity_step(const std::string& control_file, double command,
                         std::vector<std::unique_ptr<Node>> plant, double duration_s = 15);

}  // namespace tiller::test
