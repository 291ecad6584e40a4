// tiller-mission's logic: publishes a mission's path on TILLER_PATH and TILLER_MODE (waypointing,
// with the mission's is_translation) at its first tick and again every repeat period (state: a
// repeat of the same path_id does not restart the follower; it covers lost packets and late
// starters). The operator's intent is sent as events, once each (docs/safety.md):
//   * one arm request on TILLER_ARM_REQUEST at the first tick (unless arm = false), never
//     repeated, so a vehicle disarmed by a timeout or a restart stays disarmed;
//   * one START on TILLER_MISSION_COMMAND (command_id = path_id) when TILLER_ARM_STATE first says
//     armed: the mixer's safety gate lets the autonomy move the vehicle only after it.
#pragma once

#include <tiller/arm_state_t.hpp>
#include <tiller/path_t.hpp>

#include "mission/mission.hpp"
#include "runtime/node.hpp"

namespace tiller::mission {

class MissionNode : public Node {
 public:
  MissionNode(const Mission& m, std::int64_t path_id, TimeUs repeat_period_us, bool arm = true);
  void on_tick(TimeUs now) override;
  int sent() const { return sent_; }
  bool started() const { return start_sent_; }

 private:
  void on_arm_state(const arm_state_t& m, TimeUs now);

  path_t path_;
  bool translation_;
  bool arm_;
  bool arm_sent_ = false;
  bool start_sent_ = false;
  int sent_ = 0;
};

}  // namespace tiller::mission
