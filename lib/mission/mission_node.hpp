// tiller-mission's logic: publishes a mission's path on TILLER_PATH, then TILLER_MODE
// (waypointing, with the mission's is_translation) and an arm request on TILLER_ARM_REQUEST,
// at its first tick and again every repeat period (a repeat of the same path_id does not
// restart the follower; it only covers lost packets and late starters).
#pragma once

#include <tiller/path_t.hpp>

#include "mission/mission.hpp"
#include "runtime/node.hpp"

namespace tiller::mission {

class MissionNode : public Node {
 public:
  MissionNode(const Mission& m, std::int64_t path_id, TimeUs repeat_period_us, bool arm = true);
  void on_tick(TimeUs now) override;
  int sent() const { return sent_; }

 private:
  path_t path_;
  bool translation_;
  bool arm_;
  int sent_ = 0;
};

}  // namespace tiller::mission
