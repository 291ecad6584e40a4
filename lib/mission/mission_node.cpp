#include "mission/mission_node.hpp"

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/path_speed_t.hpp>

#include <algorithm>
#include <exception>

#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::mission {

MissionNode::MissionNode(const Mission& m, std::int64_t path_id, TimeUs repeat_period_us, bool arm,
                         const StartGateParams& gate, bool datum_from_vehicle)
    : Node("mission", gate.enabled || !m.items.empty() ? std::min(repeat_period_us, kGatePollUs)
                                                       : repeat_period_us),
      repeat_us_(repeat_period_us),
      path_(to_path(m, path_id, 0)),
      translation_(m.is_translation),
      arm_(arm),
      name_(m.name),
      gate_(gate) {
  set_health(heartbeat_t::STATE_OK,
             gate.enabled ? "waiting for the estimate: no odometry yet" : "publishing " + m.name);
  subscribe(channels::kArmState, &MissionNode::on_arm_state);
  if (!m.items.empty()) {
    mission_ = std::make_unique<Mission>(m);
    seq_ = std::make_unique<Sequencer>(*mission_);
    base_id_ = path_id;
    position_ = m.start ? *m.start : m.home_point;
    subscribe(channels::kPathProgress, &MissionNode::on_progress);
    advertise<path_speed_t>(channels::kPathSpeed);
    fence_breaches_ = &counter("fence.breaches");
  }
  if (gate.enabled || seq_) subscribe(channels::kOdometry, &MissionNode::on_odometry);
  if (datum_from_vehicle && mission_ && mission_->geodetic()) {
    waiting_datum_ = true;
    subscribe(channels::kDatum, &MissionNode::on_datum);
    datum_ignored_ = &counter("datum.later_ignored");
    set_health(heartbeat_t::STATE_OK, "waiting for the vehicle's datum (TILLER_DATUM)");
  }
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
  boot_nonce_ = m.boot_nonce;
  have_arm_state_ = true;
  if (path_sent_) maybe_arm(now);
  if (!m.armed || start_sent_ || (arm_ && !arm_sent_)) return;
  mission_command_t c{};
  c.utime = now;
  c.command_id = base_id_ > 0 ? base_id_ : (path_.path_id > 0 ? path_.path_id : 1);
  c.command = mission_command_t::START;
  c.source = "mission";
  publish(channels::kMissionCommand, c);
  start_sent_ = true;
}

void MissionNode::on_datum(const datum_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.datum.invalid"));  // made on first use
    return;
  }
  const GeoPoint d{m.latitude, m.longitude, m.altitude};
  if (!waiting_datum_) {
    if (d.lat_deg != datum_used_.lat_deg || d.lon_deg != datum_used_.lon_deg) ++*datum_ignored_;
    return;
  }
  try {
    relocalise(*mission_, d, name_);
  } catch (const std::exception& e) {
    set_health(heartbeat_t::STATE_DEGRADED, e.what());  // keeps waiting, publishes nothing
    return;
  }
  datum_used_ = d;
  waiting_datum_ = false;
  seq_ = std::make_unique<Sequencer>(*mission_);
  if (!have_position_) position_ = mission_->start ? *mission_->start : mission_->home_point;
  set_health(heartbeat_t::STATE_OK, "publishing " + name_ + " about the vehicle's datum");
  (void)now;
}

void MissionNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kUsPerSecond, "odometry")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.odometry.invalid"));  // made on first use
    return;
  }
  gate_.on_odometry(m, now);
  if (!seq_ || !(m.valid & odometry_t::VALID_POSITION)) return;
  have_position_ = true;
  position_.north = m.position[0];
  position_.east = m.position[1];
  if (m.valid & odometry_t::VALID_DEPTH)
    position_.depth = m.position[2];  // an ROV's leg starts here
  if (began_at_ >= 0) act(seq_->on_position(m.position[0], m.position[1], now), now);
}

void MissionNode::on_progress(const path_progress_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.path_progress.invalid"));  // made on first use
    return;
  }
  if (began_at_ < 0 || !m.complete || m.path_id != path_.path_id) return;
  act(seq_->on_leg_complete(now), now);
}

void MissionNode::send_command(std::int8_t command, TimeUs now) {
  mission_command_t c{};
  c.utime = now;
  c.command_id = base_id_ + kCommandIdOffset + commands_sent_++;
  c.command = command;
  c.source = "mission";
  publish(channels::kMissionCommand, c);
}

void MissionNode::act(Sequencer::Action a, TimeUs now) {
  if (seq_->fence_breached() && *fence_breaches_ == 0) ++*fence_breaches_;
  if (seq_->status() != shown_status_) {  // rewritten only on a change: no allocation per sample
    shown_status_ = seq_->status();
    set_health(seq_->fence_breached() ? heartbeat_t::STATE_DEGRADED : heartbeat_t::STATE_OK,
               name_ + ": " + shown_status_);
  }
  switch (a) {
    case Sequencer::Action::kNone:
      return;
    case Sequencer::Action::kNewLeg:
      leg_messages(seq_->leg(), base_id_ + seq_->leg_number() - 1, path_, speed_);
      publish_path(now);
      return;
    case Sequencer::Action::kHold:
      send_command(mission_command_t::ABORT, now);
      return;
    case Sequencer::Action::kStop:
      send_command(mission_command_t::RELEASE, now);
      return;
  }
}

void MissionNode::on_tick(TimeUs now) {
  if (waiting_datum_) return;  // nothing until the mission is in the vehicle's frame
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
    if (seq_) {
      act(seq_->begin(position_, now), now);
      return;
    }
  } else if (seq_) {
    act(seq_->on_tick(now), now);
    if (now - last_sent_ < repeat_us_) return;
  } else if (now - last_sent_ < repeat_us_) {
    return;  // gated: the tick polls the gate faster than the path repeats
  }
  publish_path(now);
}

void MissionNode::publish_path(TimeUs now) {
  last_sent_ = now;
  if (seq_) {  // the speeds first: the follower has them when the path starts
    speed_.utime = now;
    publish(channels::kPathSpeed, speed_);
  }
  path_.utime = now;
  publish(channels::kPath, path_);
  controller_mode_t mode{};
  mode.utime = now;
  mode.mode = controller_mode_t::WAYPOINTING;
  mode.is_translation = translation_;
  mode.source = "mission";
  publish(channels::kMode, mode);
  path_sent_ = true;
  maybe_arm(now);
  ++sent_;
}

void MissionNode::maybe_arm(TimeUs now) {
  // The arm request carries tiller-esc's boot nonce, so it waits for an arm state.
  if (!arm_ || arm_sent_ || !have_arm_state_) return;
  arm_request_t a{};
  a.utime = now;
  a.arm = true;
  a.source = "mission";
  a.boot_nonce = boot_nonce_;
  publish(channels::kArmRequest, a);
  arm_sent_ = true;
}

}  // namespace tiller::mission
