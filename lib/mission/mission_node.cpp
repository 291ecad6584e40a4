#include "mission/mission_node.hpp"

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/mission_command_t.hpp>

#include <algorithm>

#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::mission {

MissionNode::MissionNode(const Mission& m, std::int64_t path_id, TimeUs repeat_period_us, bool arm,
                         const StartGateParams& gate)
    : Node("mission", gate.enabled ? std::min(repeat_period_us, kGatePollUs) : repeat_period_us),
      repeat_us_(repeat_period_us),
      path_(to_path(m, path_id, 0)),
      translation_(m.is_translation),
      arm_(arm),
      name_(m.name),
      gate_(gate) {
  set_health(heartbeat_t::STATE_OK,
             gate.enabled ? "waiting for the estimate: no odometry yet" : "publishing " + m.name);
  subscribe(channels::kArmState, &MissionNode::on_arm_state);
  if (gate.enabled) subscribe(channels::kOdometry, &MissionNode::on_odometry);
  advertise<path_t>(channels::kPath);
  advertise<controller_mode_t>(channels::kMode);
  advertise<mission_command_t>(channels::kMissionCommand);
  if (arm_) advertise<arm_request_t>(channels::kArmRequest);
}

void MissionNode::on_arm_state(const arm_state_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.arm_state.invalid"));  // made on first use
    return;
  }
  if (!m.armed || start_sent_ || (arm_ && !arm_sent_)) return;
  mission_command_t c{};
  c.utime = now;
  c.command_id = path_.path_id > 0 ? path_.path_id : 1;
  c.command = mission_command_t::START;
  c.source = "mission";
  publish(channels::kMissionCommand, c);
  start_sent_ = true;
}

void MissionNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kUsPerSecond, "odometry")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.odometry.invalid"));  // made on first use
    return;
  }
  gate_.on_odometry(m, now);
}

void MissionNode::on_tick(TimeUs now) {
  if (began_at_ < 0) {
    if (!gate_.open(now)) {
      // The heartbeat (1 Hz) says why; its status is rewritten at most once a second.
      if (status_at_ < 0 || now - status_at_ >= kUsPerSecond) {
        status_at_ = now;
        set_health(heartbeat_t::STATE_OK,
                   std::string("waiting for the estimate: ") + gate_.why(now));
      }
      return;
    }
    began_at_ = now;
    set_health(heartbeat_t::STATE_OK, "publishing " + name_);
  } else if (now - last_sent_ < repeat_us_) {
    return;  // gated: the tick polls the gate faster than the path repeats
  }
  last_sent_ = now;
  path_.utime = now;
  publish(channels::kPath, path_);
  controller_mode_t mode{};
  mode.utime = now;
  mode.mode = controller_mode_t::WAYPOINTING;
  mode.is_translation = translation_;
  mode.source = "mission";
  publish(channels::kMode, mode);
  if (arm_ && !arm_sent_) {
    arm_request_t a{};
    a.utime = now;
    a.arm = true;
    a.source = "mission";
    publish(channels::kArmRequest, a);
    arm_sent_ = true;
  }
  ++sent_;
}

}  // namespace tiller::mission
