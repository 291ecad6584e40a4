// MavlinkNode flying the uploaded mission (MISSION_START): the stored items, checked and parsed by
// the .plan support (mission::parse_plan, mavlink_mission.cpp) into the one mission model, in
// lat/lon converted to metres about TILLER_DATUM, flown leg by leg by the same mission::Sequencer
// tiller-mission and the cockpit run (mission/sequencer.hpp): waypoints, loiters (time, for
// ever), return to launch, stop, jumps with their repeat counts and speed changes. Each leg goes
// out as TILLER_PATH_SPEED then TILLER_PATH; the follower's TILLER_PATH_PROGRESS (complete on the
// leg's path_id) and the odometry (the fence) move it on; a hold is an operator ABORT, a stop a
// RELEASE and a disarm request, as the cockpit does. MISSION_SET_CURRENT k: the items before k are
// left out (refused when a jump goes back before k). A return to launch or a new start ends it.
#include <exception>

#include <tiller/mission_command_t.hpp>

#include "core/message_checks.hpp"
#include "mavlink/mavlink_node.hpp"
#include "mission/plan_file.hpp"
#include "runtime/channels.hpp"

namespace tiller::mavlink {

bool MavlinkNode::build_flight(std::string& why) {
  if (stored_[MAV_MISSION_TYPE_MISSION].empty()) {
    why = "no mission uploaded";
    return false;
  }
  if (!have_datum_) {
    why = "no TILLER_DATUM yet (the mission is in lat/lon)";
    return false;
  }
  auto m = std::make_unique<mission::Mission>();
  try {
    *m = mission::parse_plan(plan_text(stored_), "the uploaded mission");
    if (current_ > 0) {  // from the current item on
      std::vector<mission::Item> kept;
      std::vector<int> moved(m->items.size(), -1);
      for (std::size_t i = 0; i < m->items.size(); ++i) {
        if (m->items[i].index < current_) continue;
        moved[i] = static_cast<int>(kept.size());
        kept.push_back(m->items[i]);
      }
      for (mission::Item& it : kept) {
        if (it.kind != mission::ItemKind::kJump) continue;
        const int to = moved[static_cast<std::size_t>(it.jump_to)];
        if (to < 0) {
          why = "item " + std::to_string(it.index) + " jumps before the current item";
          return false;
        }
        it.jump_to = to;
      }
      m->items = std::move(kept);
      if (m->items.empty()) {
        why = "the mission has no item from the current one on";
        return false;
      }
    }
    mission::finish_items(*m, "the uploaded mission",
                          mission::GeoPoint{datum_.latitude, datum_.longitude, datum_.altitude});
  } catch (const std::exception& e) {
    why = e.what();
    return false;
  }
  end_flight();
  flight_ = std::move(m);
  seq_ = std::make_unique<mission::Sequencer>(*flight_);
  return true;
}

void MavlinkNode::begin_flight(TimeUs now) {
  last_id_ = std::max<std::int64_t>(now, last_id_ + 1);
  flight_base_ = last_id_;
  last_id_ += 100000;  // the legs' path ids: base, base + 1, ...
  mission::MissionPoint from = flight_->home_point;
  if (have_odom_ && (odom_.valid & odometry_t::VALID_POSITION)) {
    from.north = odom_.position[0];
    from.east = odom_.position[1];
  }
  fly(seq_->begin(from, now), now);
  set_mode(controller_mode_t::WAYPOINTING, now);
  mission_command_t mc{};
  mc.utime = now;
  mc.command_id = ++last_id_;
  mc.command = mission_command_t::START;
  mc.source = "mavlink";
  publish(channels::kMissionCommand, mc);
}

void MavlinkNode::fly(mission::Sequencer::Action a, TimeUs now) {
  using Action = mission::Sequencer::Action;
  if (seq_->status() != flight_status_) {
    flight_status_ = seq_->status();
    if (!flight_status_.empty()) statustext(MAV_SEVERITY_INFO, "mission: " + flight_status_, now);
  }
  if (a == Action::kNewLeg) {
    mission::leg_messages(seq_->leg(), flight_base_ + seq_->leg_number() - 1, leg_path_,
                          leg_speed_);
    leg_speed_.utime = now;
    publish(channels::kPathSpeed, leg_speed_);  // first: the follower has them when the path starts
    leg_path_.utime = now;
    publish(channels::kPath, leg_path_);
    return;
  }
  if (a != Action::kHold && a != Action::kStop) return;
  mission_command_t mc{};  // hold: an operator ABORT; stop: RELEASE, and a disarm request
  mc.utime = now;
  mc.command_id = ++last_id_;
  mc.command = a == Action::kHold ? mission_command_t::ABORT : mission_command_t::RELEASE;
  mc.source = "mavlink (mission)";
  publish(channels::kMissionCommand, mc);
  if (a == Action::kStop) arm(false, now);
}

void MavlinkNode::end_flight() {
  seq_.reset();  // the sequencer refers to flight_: gone first
  flight_.reset();
  flight_status_.clear();
}

void MavlinkNode::on_progress(const path_progress_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {  // its contract first: a bad one is counted, never acted on
    reject(counter("rejected.path_progress.invalid"));  // made on first use
    return;
  }
  if (!seq_ || !m.complete || m.path_id != leg_path_.path_id) return;
  fly(seq_->on_leg_complete(now), now);
}

}  // namespace tiller::mavlink
