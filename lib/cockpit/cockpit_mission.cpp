// CockpitNode's missions: an uploaded mission file (YAML, CSV or a QGroundControl .plan) parsed
// by the injected loader, in lat/lon converted to metres about the vehicle's datum (TILLER_DATUM
// from tiller-nav or tiller-sim, the frame its odometry is in; a lat/lon upload before one has
// come is refused); a plain path published as it is, a mission with items (loiter, return home,
// speed, jump, fence) flown leg by leg by the same mission::Sequencer tiller-mission runs
// (mission/sequencer.hpp), on the vehicle's odometry and the follower's progress. The page's map
// gets the plan in a "mission" frame: every item's point, home, rally points and the fence.
#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/mission_command_t.hpp>

#include "cockpit/cockpit_node_parts.hpp"
#include "runtime/channels.hpp"

namespace tiller::cockpit {

using nlohmann::json;

namespace {

json point(const mission::MissionPoint& p) {
  return json::array({p.north, p.east});
}

}  // namespace

void CockpitNode::on_mission_load(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  const std::string_view cmd = "mission_load";
  const json* name = member(j, "name");
  const json* body = member(j, "text");
  if (!name || !name->is_string() || !body || !body->is_string()) {
    refuse(client, cmd, *bad_command_, "mission_load: expected \"name\" and \"text\" strings");
    return;
  }
  mission::Mission m;
  try {
    m = loader_(name->get<std::string>(), body->get<std::string>(),
                have_datum_ ? std::optional<mission::GeoPoint>(datum_) : std::nullopt);
  } catch (const std::exception& e) {
    refuse(client, cmd, *bad_mission_, e.what());
    return;
  }
  if (m.geodetic() && !have_datum_) {
    refuse(client, cmd, *bad_mission_,
           name->get<std::string>() +
               ": a mission in latitude/longitude needs the vehicle's datum (TILLER_DATUM, from "
               "tiller-nav or tiller-sim), and none has come yet");
    return;
  }
  end_mission();
  const std::int64_t id = next_id(now);
  std::string what = std::to_string(m.waypoints.size()) + " waypoints";
  if (m.items.empty()) {
    path_ = mission::to_path(m, id, 0);
  } else {
    items_ = std::make_unique<mission::Mission>(std::move(m));
    seq_ = std::make_unique<mission::Sequencer>(*items_);
    base_id_ = id;
    what = std::to_string(items_->items.size()) + " items";
  }
  const mission::Mission& loaded = items_ ? *items_ : m;
  path_active_ = true;
  write_mission_frame(loaded);
  emit(kEveryClient);  // once per load: never replaced by a state frame before it is sent
  if (seq_) {
    // The first leg starts where the vehicle is (else where the plan starts it, or home).
    const mission::MissionPoint from =
        have_position_ ? position_ : (loaded.start ? *loaded.start : loaded.home_point);
    fly_items(seq_->begin(from, now), now);
  } else {
    publish_mission_path(now);
  }
  controller_mode_t c{};
  c.utime = now;
  c.mode = controller_mode_t::WAYPOINTING;
  c.is_translation = loaded.is_translation;
  c.source = "cockpit";
  publish(channels::kMode, c);
  ++*accepted_;
  reply(client, cmd, true,
        loaded.name + ": " + what + ", path_id " + std::to_string(path_.path_id) +
            " (mode WAYPOINTING; arm, then start)");
}

void CockpitNode::publish_mission_path(TimeUs now) {
  if (seq_) {  // the speeds first: the follower has them when the path starts
    speed_.utime = now;
    publish(channels::kPathSpeed, speed_);
  }
  path_.utime = now;
  publish(channels::kPath, path_);
  path_sent_ = now;
}

void CockpitNode::fly_items(mission::Sequencer::Action a, TimeUs now) {
  if (seq_->fence_breached() && *fence_breaches_ == 0) ++*fence_breaches_;
  if (seq_->status() != items_status_) {
    items_status_ = seq_->status();
    set_health(seq_->fence_breached() ? heartbeat_t::STATE_DEGRADED : heartbeat_t::STATE_OK,
               items_->name + ": " + items_status_);
  }
  using Action = mission::Sequencer::Action;
  if (a == Action::kNewLeg) {
    mission::leg_messages(seq_->leg(), base_id_ + seq_->leg_number() - 1, path_, speed_);
    publish_mission_path(now);
    return;
  }
  if (a != Action::kHold && a != Action::kStop) return;
  mission_command_t mc{};  // hold: an operator ABORT; stop: RELEASE, the mixer disarms
  mc.utime = now;
  mc.command_id = next_id(now);
  mc.command = a == Action::kHold ? mission_command_t::ABORT : mission_command_t::RELEASE;
  mc.source = "cockpit (mission)";
  publish(channels::kMissionCommand, mc);
  if (a == Action::kStop) {
    arm_request_t r{};
    r.utime = now;
    r.arm = false;
    r.source = "cockpit (mission stop)";
    r.station = p_.station;
    publish(channels::kArmRequest, r);
  }
}

void CockpitNode::on_items_odometry(const odometry_t& m, TimeUs now) {
  if (!(m.valid & odometry_t::VALID_POSITION)) return;
  have_position_ = true;
  position_.north = m.position[0];
  position_.east = m.position[1];
  if (m.valid & odometry_t::VALID_DEPTH)
    position_.depth = m.position[2];  // an ROV's leg starts here
  if (!seq_ || !path_active_) return;
  fly_items(seq_->on_position(m.position[0], m.position[1], now), now);
}

void CockpitNode::on_items_progress(const path_progress_t& m, TimeUs now) {
  if (!seq_ || !path_active_ || !m.complete || m.path_id != path_.path_id) return;
  fly_items(seq_->on_leg_complete(now), now);
}

void CockpitNode::end_mission() {
  path_active_ = false;
  seq_.reset();  // the sequencer refers to items_: gone first
  items_.reset();
  items_status_.clear();
}

void CockpitNode::write_mission_frame(const mission::Mission& m) {
  json fence = json::array();
  for (const auto& f : m.fence) {
    json s = {{"inclusion", f.inclusion}, {"circle", f.circle}};
    if (f.circle) {
      s["centre"] = point(f.centre);
      s["radius"] = f.radius_m;
    } else {
      json poly = json::array();
      for (const auto& v : f.polygon) poly.push_back(point(v));
      s["polygon"] = poly;
    }
    fence.push_back(s);
  }
  json points = json::array(), rally = json::array();
  for (const auto& w : m.waypoints) points.push_back(point(w));
  for (const auto& r : m.rally) rally.push_back(point(r));
  json frame = {{"type", "mission"},       {"name", m.name}, {"points", points},
                {"items", m.items.size()}, {"fence", fence}, {"rally", rally}};
  if (!m.items.empty()) frame["home"] = point(m.home_point);
  if (m.geodetic())
    frame["datum"] = {{"lat", datum_.lat_deg}, {"lon", datum_.lon_deg}, {"alt", datum_.alt_m}};
  mission_frame_ = frame.dump();
  frame_ = mission_frame_;
}

}  // namespace tiller::cockpit
