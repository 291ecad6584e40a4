#include "step_response.hpp"

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/odometry_t.hpp>

#include <cmath>

#include "control/control_config.hpp"
#include "control/velocity_pid_node.hpp"
#include "harness.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {

StepResult velocity_step(const std::string& control_file, double command,
                         std::vector<std::unique_ptr<Node>> plant, double duration_s,
                         StepAxis axis) {
  auto p =
      control::load_velocity_pid_node_params(config::Value::load_file(source_path(control_file)));
  p.arbiter.default_mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  control::VelocityPidNode vpid(p);
  LockstepExecutor ex(0);
  for (auto& n : plant) ex.add(*n);
  ex.add(vpid);
  StepResult r;
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    if (ch == channels::kOdometry && o.decode(d, 0, n) == n) {
      r.t.push_back(to_seconds(t));
      r.u.push_back(o.velocity[static_cast<int>(axis)]);
    }
  });
  manual_velocity_cmd_t m{};
  if (axis == StepAxis::kYawRate) {
    m.yaw_rate = command;
  } else {
    m.velocity[static_cast<int>(axis)] = command;
  }
  m.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
  m.valid = true;
  const TimeUs end = from_seconds(duration_s);
  arm_request_t arm{};
  arm.arm = true;
  arm.source = "step-test";
  for (TimeUs t = 0; t <= end; t += kUsPerSecond) {  // the full stack's ESC node arms on this
    arm.utime = t;
    ex.inject(channels::kArmRequest, arm, t);
  }
  manual_demand_t centred{};  // the teleop's stick, centred: the safety gate's start condition
  centred.valid = true;
  for (TimeUs t = 0; t <= end; t += 50'000) {
    m.utime = t;
    ex.inject(channels::kManualVelocity, m, t);
    centred.utime = t;
    ex.inject(channels::kManualDemand, centred, t);
  }
  ex.run_until(end);
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < r.u.size(); ++k) {
    r.peak = std::max(r.peak, r.u[k]);
    if (r.rise_s < 0 && r.u[k] >= 0.9 * command) r.rise_s = r.t[k];
    if (std::abs(r.u[k] - command) > 0.05 * command)
      r.settle_s = -1;
    else if (r.settle_s < 0)
      r.settle_s = r.t[k];
    if (r.t[k] > duration_s - 2) {
      sum += r.u[k];
      ++n;
    }
  }
  r.final_speed = n ? sum / n : 0;
  r.overshoot = std::max(0.0, (r.peak - command) / command);
  return r;
}

}  // namespace tiller::test
