// MavlinkNode's mission protocol (https://mavlink.io/en/services/mission.html), the INT variant:
// upload (MISSION_COUNT, then MISSION_REQUEST_INT for each item in turn, re-asked after
// mission_retry_s up to 5 times, MISSION_ACK at the end), download (MISSION_REQUEST_LIST ->
// MISSION_COUNT, MISSION_REQUEST_INT -> MISSION_ITEM_INT), MISSION_CLEAR_ALL and
// MISSION_SET_CURRENT (-> MISSION_CURRENT), for missions, fences and rally points.
// An uploaded set is checked as the .plan support checks a file: the items (with the stored fence
// and rally points) are written as a QGroundControl .plan and parsed by mission::parse_plan, so the
// same items are accepted (16, 17, 19, 20, 21, 177, 178; fence 5001-5004; rally 5100) and the
// same are refused, with its reason as a STATUSTEXT and MISSION_ACK MAV_MISSION_UNSUPPORTED.
// MISSION_START flies the parsed mission (mavlink_fly.cpp).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <exception>

#include "mavlink/mavlink_node.hpp"
#include "mission/mission.hpp"
#include "mission/plan_file.hpp"

namespace tiller::mavlink {

namespace {

constexpr int kMaxRetries = 5;
constexpr std::uint16_t kMaxItems = 1000;

}  // namespace

std::string plan_text(const std::array<std::vector<MavlinkNode::MissionItem>, 3>& s) {
  using nlohmann::json;
  json items = json::array();
  int jump_id = 1;
  for (const auto& it : s[MAV_MISSION_TYPE_MISSION]) {
    json p = json::array(
        {it.params[0], it.params[1], it.params[2], it.params[3], it.x / 1e7, it.y / 1e7, it.z});
    if (it.command == MAV_CMD_DO_JUMP) p[0] = it.params[0] + 1;  // seq -> doJumpId (seq + 1)
    items.push_back({{"type", "SimpleItem"},
                     {"command", it.command},
                     {"frame", it.frame},
                     {"params", p},
                     {"doJumpId", jump_id++},
                     {"autoContinue", it.autocontinue}});
  }
  json polygons = json::array(), circles = json::array();
  const auto& f = s[MAV_MISSION_TYPE_FENCE];
  for (std::size_t i = 0; i < f.size();) {
    const auto& it = f[i];
    if (it.command == MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION ||
        it.command == MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION) {
      circles.push_back(
          {{"inclusion", it.command == MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION},
           {"circle", {{"center", {it.x / 1e7, it.y / 1e7}}, {"radius", it.params[0]}}}});
      ++i;
      continue;
    }
    // A polygon: params[0] vertices of the same command.
    const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(it.params[0]));
    json poly = json::array();
    for (std::size_t k = 0; k < n && i + k < f.size(); ++k)
      poly.push_back({f[i + k].x / 1e7, f[i + k].y / 1e7});
    polygons.push_back({{"inclusion", it.command == MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION},
                        {"polygon", poly}});
    i += n;
  }
  json rally = json::array();
  for (const auto& it : s[MAV_MISSION_TYPE_RALLY]) rally.push_back({it.x / 1e7, it.y / 1e7, it.z});
  json home = json::array({0, 0, 0});
  for (const auto& it : s[MAV_MISSION_TYPE_MISSION])
    if (it.x != 0 || it.y != 0) {
      home = json::array({it.x / 1e7, it.y / 1e7, 0});
      break;
    }
  json plan = {{"fileType", "Plan"},
               {"version", 1},
               {"groundStation", "tiller-mavlink"},
               {"mission",
                {{"version", 2},
                 {"firmwareType", 0},
                 {"vehicleType", 10},
                 {"cruiseSpeed", 1},
                 {"hoverSpeed", 1},
                 {"plannedHomePosition", home},
                 {"items", items}}},
               {"geoFence", {{"version", 2}, {"polygons", polygons}, {"circles", circles}}},
               {"rallyPoints", {{"version", 2}, {"points", rally}}}};
  return plan.dump();
}

void MavlinkNode::mission_ack(std::uint8_t sysid, std::uint8_t compid, std::uint8_t type,
                              std::uint8_t result, TimeUs now) {
  mavlink_message_t out;
  mavlink_msg_mission_ack_pack_status(p_.system_id, p_.component_id, writer_.status(), &out, sysid,
                                      compid, result, type, 0);
  send(out, now);
}

void MavlinkNode::request_item(TimeUs now) {
  mavlink_message_t out;
  mavlink_msg_mission_request_int_pack_status(p_.system_id, p_.component_id, writer_.status(), &out,
                                              up_.sysid, up_.compid, up_.next, up_.type);
  up_.asked = now;
  send(out, now);
}

void MavlinkNode::mission_tick(TimeUs now) {
  if (!up_.active || now - up_.asked < p_.mission_retry) return;
  if (++up_.retries > kMaxRetries) {
    up_.active = false;
    reject(*mission_refused_);
    statustext(MAV_SEVERITY_WARNING, "mission upload timed out", now);
    mission_ack(up_.sysid, up_.compid, up_.type, MAV_MISSION_OPERATION_CANCELLED, now);
    return;
  }
  request_item(now);
}

void MavlinkNode::send_item(const mavlink_message_t& req, std::uint16_t seq, std::uint8_t type,
                            TimeUs now) {
  const auto& set = stored_[type];
  if (seq >= set.size()) {
    mission_ack(req.sysid, req.compid, type, MAV_MISSION_INVALID_SEQUENCE, now);
    return;
  }
  const MissionItem& it = set[seq];
  mavlink_message_t out;
  mavlink_msg_mission_item_int_pack_status(
      p_.system_id, p_.component_id, writer_.status(), &out, req.sysid, req.compid, seq, it.frame,
      it.command, seq == current_ && type == MAV_MISSION_TYPE_MISSION, it.autocontinue,
      it.params[0], it.params[1], it.params[2], it.params[3], it.x, it.y, it.z, type);
  send(out, now);
}

void MavlinkNode::upload_done(TimeUs now) {
  auto sets = stored_;
  sets[up_.type] = up_.items;
  up_.active = false;
  try {
    (void)mission::parse_plan(plan_text(sets), "the uploaded mission");
  } catch (const std::exception& e) {
    reject(*mission_refused_);
    statustext(MAV_SEVERITY_WARNING, e.what(), now);
    mission_ack(up_.sysid, up_.compid, up_.type, MAV_MISSION_UNSUPPORTED, now);
    return;
  }
  stored_ = std::move(sets);
  if (up_.type == MAV_MISSION_TYPE_MISSION) current_ = 0;
  mission_ack(up_.sysid, up_.compid, up_.type, MAV_MISSION_ACCEPTED, now);
}

void MavlinkNode::on_mission(const mavlink_message_t& msg, TimeUs now) {
  switch (msg.msgid) {
    case MAVLINK_MSG_ID_MISSION_COUNT: {
      mavlink_mission_count_t c;
      mavlink_msg_mission_count_decode(&msg, &c);
      if (c.target_system != p_.system_id) return;
      if (!from_gcs(msg, now)) {
        mission_ack(msg.sysid, msg.compid, c.mission_type, MAV_MISSION_DENIED, now);
        return;
      }
      if (c.mission_type >= kMissionTypes || c.count > kMaxItems) {
        reject(*mission_refused_);
        mission_ack(msg.sysid, msg.compid, c.mission_type,
                    c.count > kMaxItems ? MAV_MISSION_NO_SPACE : MAV_MISSION_UNSUPPORTED, now);
        return;
      }
      up_ = Upload{true, c.mission_type, msg.sysid, msg.compid, c.count, 0, now, 0, {}};
      up_.items.reserve(c.count);
      if (c.count == 0) {
        upload_done(now);
        return;
      }
      request_item(now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_ITEM_INT: {
      mavlink_mission_item_int_t it;
      mavlink_msg_mission_item_int_decode(&msg, &it);
      if (it.target_system != p_.system_id || !up_.active || msg.sysid != up_.sysid ||
          it.mission_type != up_.type)
        return;
      if (it.seq != up_.next) return;  // a repeat or out of order: the request stands
      MissionItem m;
      m.command = it.command;
      m.frame = it.frame;
      m.params[0] = it.param1;
      m.params[1] = it.param2;
      m.params[2] = it.param3;
      m.params[3] = it.param4;
      m.x = it.x;
      m.y = it.y;
      m.z = it.z;
      m.autocontinue = it.autocontinue != 0;
      up_.items.push_back(m);
      up_.retries = 0;
      if (++up_.next == up_.count) {
        upload_done(now);
        return;
      }
      request_item(now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_REQUEST_LIST: {
      mavlink_mission_request_list_t r;
      mavlink_msg_mission_request_list_decode(&msg, &r);
      if (r.target_system != p_.system_id) return;
      if (r.mission_type >= kMissionTypes) {
        mission_ack(msg.sysid, msg.compid, r.mission_type, MAV_MISSION_UNSUPPORTED, now);
        return;
      }
      mavlink_message_t out;
      mavlink_msg_mission_count_pack_status(
          p_.system_id, p_.component_id, writer_.status(), &out, msg.sysid, msg.compid,
          static_cast<std::uint16_t>(stored_[r.mission_type].size()), r.mission_type, 0);
      send(out, now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_REQUEST_INT: {
      mavlink_mission_request_int_t r;
      mavlink_msg_mission_request_int_decode(&msg, &r);
      if (r.target_system != p_.system_id || r.mission_type >= kMissionTypes) return;
      send_item(msg, r.seq, r.mission_type, now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_REQUEST: {  // the float variant: answered with the INT item
      mavlink_mission_request_t r;
      mavlink_msg_mission_request_decode(&msg, &r);
      if (r.target_system != p_.system_id || r.mission_type >= kMissionTypes) return;
      send_item(msg, r.seq, r.mission_type, now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_ACK:
      return;  // the end of a download
    case MAVLINK_MSG_ID_MISSION_CLEAR_ALL: {
      mavlink_mission_clear_all_t c;
      mavlink_msg_mission_clear_all_decode(&msg, &c);
      if (c.target_system != p_.system_id) return;
      if (!from_gcs(msg, now)) {
        mission_ack(msg.sysid, msg.compid, c.mission_type, MAV_MISSION_DENIED, now);
        return;
      }
      if (c.mission_type == MAV_MISSION_TYPE_ALL) {
        for (auto& s : stored_) s.clear();
      } else if (c.mission_type < kMissionTypes) {
        stored_[c.mission_type].clear();
      }
      current_ = 0;
      mission_ack(msg.sysid, msg.compid, c.mission_type, MAV_MISSION_ACCEPTED, now);
      return;
    }
    case MAVLINK_MSG_ID_MISSION_SET_CURRENT: {
      mavlink_mission_set_current_t c;
      mavlink_msg_mission_set_current_decode(&msg, &c);
      if (c.target_system != p_.system_id || !from_gcs(msg, now)) return;
      if (c.seq >= stored_[MAV_MISSION_TYPE_MISSION].size()) {
        statustext(MAV_SEVERITY_WARNING, "set current refused: no such item", now);
        return;
      }
      current_ = c.seq;
      mavlink_message_t out;
      mavlink_msg_mission_current_pack_status(
          p_.system_id, p_.component_id, writer_.status(), &out, current_,
          static_cast<std::uint16_t>(stored_[MAV_MISSION_TYPE_MISSION].size()), 0, 0, 0, 0, 0);
      send(out, now);
      return;
    }
    default:
      return;
  }
}

}  // namespace tiller::mavlink
