// MavlinkNode's commands (COMMAND_LONG / COMMAND_INT, SET_MODE), MANUAL_CONTROL as a pilot source,
// the telemetry rate requests and the parameter protocol (mavlink/mavlink_node.hpp). Every command
// that acts becomes the LCM message a teleop station or the cockpit would send, once.
#include <algorithm>
#include <cmath>
#include <cstring>

#include <tiller/arm_request_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/path_t.hpp>

#include "mavlink/mavlink_node.hpp"
#include "runtime/channels.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller::mavlink {

void MavlinkNode::ack(const mavlink_message_t& msg, std::uint16_t cmd, std::uint8_t result,
                      TimeUs now) {
  mavlink_message_t out;
  mavlink_msg_command_ack_pack_status(p_.system_id, p_.component_id, writer_.status(), &out, cmd,
                                      result, 0, 0, msg.sysid, msg.compid);
  send(out, now);
}

void MavlinkNode::on_command(const mavlink_message_t& msg, std::uint16_t cmd, const float (&prm)[7],
                             TimeUs now) {
  // Requests that only read: any station.
  switch (cmd) {
    case MAV_CMD_SET_MESSAGE_INTERVAL:
      set_interval(static_cast<std::uint32_t>(prm[0]), prm[1]);
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);
      return;
    case MAV_CMD_REQUEST_MESSAGE:
    case MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES: {
      const std::uint32_t id = cmd == MAV_CMD_REQUEST_MESSAGE ? static_cast<std::uint32_t>(prm[0])
                                                              : MAVLINK_MSG_ID_AUTOPILOT_VERSION;
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);
      if (id == MAVLINK_MSG_ID_AUTOPILOT_VERSION) {
        const std::uint8_t none[8] = {};
        const std::uint8_t uid2[18] = {};
        mavlink_message_t out;
        mavlink_msg_autopilot_version_pack_status(
            p_.system_id, p_.component_id, writer_.status(), &out,
            MAV_PROTOCOL_CAPABILITY_MISSION_INT | MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT |
                MAV_PROTOCOL_CAPABILITY_COMMAND_INT | MAV_PROTOCOL_CAPABILITY_MAVLINK2 |
                MAV_PROTOCOL_CAPABILITY_MISSION_FENCE | MAV_PROTOCOL_CAPABILITY_MISSION_RALLY,
            0, 0, 0, 0, none, none, none, 0, 0, 0, uid2);
        send(out, now);
      } else {
        send_stream(id, now);
      }
      return;
    }
    default:
      break;
  }
  if (!from_gcs(msg, now)) {
    ++*commands_refused_;
    ack(msg, cmd, MAV_RESULT_DENIED, now);
    return;
  }
  switch (cmd) {
    case MAV_CMD_COMPONENT_ARM_DISARM:
      if (prm[0] != 0.0f && prm[0] != 1.0f) break;
      arm(prm[0] == 1.0f, now);
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);  // sent; tiller-esc decides (its reason follows)
      return;
    case MAV_CMD_DO_SET_MODE: {
      const int base = static_cast<int>(prm[0]);
      const float custom = prm[1];
      if (!(base & MAV_MODE_FLAG_CUSTOM_MODE_ENABLED) || !(custom >= 0 && custom <= 8) ||
          custom != std::floor(custom))
        break;
      set_mode(static_cast<std::int8_t>(custom), now);
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);
      return;
    }
    case MAV_CMD_NAV_RETURN_TO_LAUNCH: {
      if (!have_odom_ || !(odom_.valid & odometry_t::VALID_POSITION)) {
        statustext(MAV_SEVERITY_WARNING, "return refused: no valid position", now);
        ++*commands_refused_;
        ack(msg, cmd, MAV_RESULT_TEMPORARILY_REJECTED, now);
        return;
      }
      end_flight();
      start_path({{odom_.position[0], odom_.position[1]}, {0.0, 0.0}}, now);
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);
      return;
    }
    case MAV_CMD_MISSION_START: {
      std::string why;
      if (!build_flight(why)) {
        statustext(MAV_SEVERITY_WARNING, "mission start refused: " + why, now);
        ++*commands_refused_;
        ack(msg, cmd, MAV_RESULT_DENIED, now);
        return;
      }
      begin_flight(now);
      ack(msg, cmd, MAV_RESULT_ACCEPTED, now);
      return;
    }
    default:
      ++*commands_refused_;
      ack(msg, cmd, MAV_RESULT_UNSUPPORTED, now);
      return;
  }
  ++*commands_refused_;
  statustext(MAV_SEVERITY_WARNING, "command " + std::to_string(cmd) + " refused: bad parameters",
             now);
  ack(msg, cmd, MAV_RESULT_DENIED, now);
}

void MavlinkNode::arm(bool on, TimeUs now) {
  arm_request_t a{};
  a.utime = now;
  a.arm = on;
  a.source = "mavlink";
  a.station = p_.station;
  a.boot_nonce = arm_.boot_nonce;
  a.takeover = false;
  publish(channels::kArmRequest, a);
  ++*commands_;
}

void MavlinkNode::set_mode(std::int8_t mode, TimeUs now) {
  controller_mode_t c{};
  c.utime = now;
  c.mode = mode;
  c.is_translation = false;
  c.source = "mavlink";
  publish(channels::kMode, c);
  ++*commands_;
}

void MavlinkNode::start_path(const std::vector<std::array<double, 2>>& points, TimeUs now) {
  last_id_ = std::max<std::int64_t>(now, last_id_ + 1);
  path_t path{};
  path.utime = now;
  path.path_id = last_id_;
  path.n_waypoints = static_cast<std::int32_t>(points.size());
  for (const auto& pt : points) {
    waypoint_t w{};
    w.position[0] = pt[0];
    w.position[1] = pt[1];
    w.has_heading = false;
    path.waypoints.push_back(w);
  }
  publish(channels::kPath, path);
  set_mode(controller_mode_t::WAYPOINTING, now);
  mission_command_t mc{};
  mc.utime = now;
  mc.command_id = last_id_;
  mc.command = mission_command_t::START;
  mc.source = "mavlink";
  publish(channels::kMissionCommand, mc);
}

// ---------------------------------------------------------------- MANUAL_CONTROL

void MavlinkNode::publish_demand(bool valid, TimeUs now) {
  demand_.utime = now;
  if (!valid) std::fill(std::begin(demand_.demand), std::end(demand_.demand), 0.0);
  demand_.valid = valid;
  publish(channels::kManualDemand, demand_);
}

void MavlinkNode::on_manual_control(const mavlink_message_t& msg, TimeUs now) {
  mavlink_manual_control_t m;
  mavlink_msg_manual_control_decode(&msg, &m);
  if (m.target != p_.system_id) {
    ++*other_target_;
    return;
  }
  if (!from_gcs(msg, now)) return;
  auto axis = [](std::int16_t v) { return v == INT16_MAX ? 0.0 : v / 1000.0; };
  const double zc = p_.z_centre;
  const double heave =
      !p_.submarine || m.z == INT16_MAX ? 0.0 : -(m.z - zc) / std::max(1.0, 1000.0 - zc);
  const double raw[4] = {axis(m.x), axis(m.y), heave, axis(m.r)};
  bool ok = true;
  for (double v : raw) ok = ok && std::isfinite(v) && std::fabs(v) <= 1.0 + 1e-9;
  if (!ok) {
    reject(*bad_manual_);
    centred_ = false;
    publish_demand(false, now);
    return;
  }
  const double dz = p_.params[kManDeadzone];
  const double g = p_.params[kManGain];
  double d[6] = {};
  bool inside = true;
  const int dof[4] = {0, 1, 2, 5};
  for (int i = 0; i < 4; ++i) {
    const double s = shape_axis(std::clamp(raw[i], -1.0, 1.0), dz, 0.0);
    if (s != 0.0) inside = false;
    d[dof[i]] = std::clamp(s * g * (i == 3 ? p_.params[kManYawGain] : 1.0), -1.0, 1.0);
  }
  pilot_rx_ = now;
  if (!centred_) centred_ = inside;
  if (!centred_) {
    publish_demand(false, now);
    return;
  }
  for (int i = 0; i < 6; ++i) demand_.demand[i] = d[i];
  publish_demand(true, now);
}

// ---------------------------------------------------------------- rates

void MavlinkNode::set_interval(std::uint32_t msgid, double interval_us) {
  for (Stream& s : streams_) {
    if (s.msgid != msgid) continue;
    if (interval_us == 0) {  // the default
      s.interval = msgid == MAVLINK_MSG_ID_HEARTBEAT ? 1000000 : 1000000;
    } else {
      s.interval = interval_us < 0 ? 0 : std::max<TimeUs>(static_cast<TimeUs>(interval_us), 10000);
    }
    s.next = 0;
  }
}

void MavlinkNode::on_data_stream(const mavlink_message_t& msg) {
  mavlink_request_data_stream_t r;
  mavlink_msg_request_data_stream_decode(&msg, &r);
  if (r.target_system != p_.system_id) return;
  const TimeUs iv = r.start_stop == 0 || r.req_message_rate == 0
                        ? 0
                        : std::max<TimeUs>(1000000 / r.req_message_rate, 10000);
  auto in = [&](std::uint32_t id) {
    switch (r.req_stream_id) {
      case MAV_DATA_STREAM_ALL:
        return id != MAVLINK_MSG_ID_HEARTBEAT;
      case MAV_DATA_STREAM_EXTENDED_STATUS:
        return id == MAVLINK_MSG_ID_SYS_STATUS || id == MAVLINK_MSG_ID_GPS_RAW_INT;
      case MAV_DATA_STREAM_RC_CHANNELS:
        return id == MAVLINK_MSG_ID_SERVO_OUTPUT_RAW;
      case MAV_DATA_STREAM_POSITION:
        return id == MAVLINK_MSG_ID_GLOBAL_POSITION_INT;
      case MAV_DATA_STREAM_EXTRA1:
        return id == MAVLINK_MSG_ID_ATTITUDE;
      case MAV_DATA_STREAM_EXTRA2:
        return id == MAVLINK_MSG_ID_VFR_HUD;
      case MAV_DATA_STREAM_EXTRA3:
        return id == MAVLINK_MSG_ID_BATTERY_STATUS;
      default:
        return false;
    }
  };
  for (Stream& s : streams_) {
    if (!in(s.msgid)) continue;
    s.interval = iv;
    s.next = 0;
  }
}

// ---------------------------------------------------------------- parameters

std::size_t MavlinkNode::param_count() const {
  return kParamCount + p_.gains.size();
}

void MavlinkNode::send_param(std::size_t i, TimeUs now) {
  char id[MAVLINK_MSG_PARAM_VALUE_FIELD_PARAM_ID_LEN + 1] = {};
  const bool own = i < kParamCount;
  std::strncpy(id, own ? kParams[i].id : p_.gains[i - kParamCount].id.c_str(),
               MAVLINK_MSG_PARAM_VALUE_FIELD_PARAM_ID_LEN);
  const double v = own ? p_.params[i] : p_.gains[i - kParamCount].value;
  mavlink_message_t out;
  mavlink_msg_param_value_pack_status(p_.system_id, p_.component_id, writer_.status(), &out, id,
                                      static_cast<float>(v), MAV_PARAM_TYPE_REAL32,
                                      static_cast<std::uint16_t>(param_count()),
                                      static_cast<std::uint16_t>(i));
  send(out, now);
}

void MavlinkNode::on_param(const mavlink_message_t& msg, TimeUs now) {
  auto find = [this](const char* id16) -> int {
    char id[17] = {};
    std::memcpy(id, id16, 16);
    for (std::size_t i = 0; i < kParamCount; ++i)
      if (std::strcmp(id, kParams[i].id) == 0) return static_cast<int>(i);
    for (std::size_t i = 0; i < p_.gains.size(); ++i)
      if (p_.gains[i].id == id) return static_cast<int>(kParamCount + i);
    return -1;
  };
  const int n = static_cast<int>(param_count());
  if (msg.msgid == MAVLINK_MSG_ID_PARAM_REQUEST_LIST) {
    mavlink_param_request_list_t r;
    mavlink_msg_param_request_list_decode(&msg, &r);
    if (r.target_system != p_.system_id) return;
    for (int i = 0; i < n; ++i) send_param(static_cast<std::size_t>(i), now);
    return;
  }
  if (msg.msgid == MAVLINK_MSG_ID_PARAM_REQUEST_READ) {
    mavlink_param_request_read_t r;
    mavlink_msg_param_request_read_decode(&msg, &r);
    if (r.target_system != p_.system_id) return;
    const int i = r.param_index >= 0 ? r.param_index : find(r.param_id);
    if (i >= 0 && i < n) send_param(static_cast<std::size_t>(i), now);
    return;
  }
  mavlink_param_set_t s;
  mavlink_msg_param_set_decode(&msg, &s);
  if (s.target_system != p_.system_id) return;
  const int i = find(s.param_id);
  if (!from_gcs(msg, now)) {
    reject(*param_refused_);
    if (i >= 0) send_param(static_cast<std::size_t>(i), now);
    return;
  }
  if (i < 0) {
    reject(*param_refused_);
    statustext(MAV_SEVERITY_WARNING, "param set refused: no such parameter", now);
    return;
  }
  const std::size_t k = static_cast<std::size_t>(i);
  const bool own = k < kParamCount;
  GainParam* gain = own ? nullptr : &p_.gains[k - kParamCount];
  const char* name = own ? kParams[k].id : gain->id.c_str();
  const double lo = own ? kParams[k].min : gain->min, hi = own ? kParams[k].max : gain->max;
  const double v = s.param_value;
  const bool integer = k == kSysidMygcs;
  if (!std::isfinite(v) || v < lo || v > hi || (integer && v != std::floor(v))) {
    reject(*param_refused_);
    char buf[96];
    if (hi < 1e300)
      std::snprintf(buf, sizeof buf, "%s refused: %g outside [%g, %g]", name, v, lo, hi);
    else if (lo > 0 && lo < 1e-300)  // config::Range::positive()
      std::snprintf(buf, sizeof buf, "%s refused: %g, not > 0", name, v);
    else
      std::snprintf(buf, sizeof buf, "%s refused: %g, not >= %g", name, v, lo);
    statustext(MAV_SEVERITY_WARNING, buf, now);
  } else if (own) {
    p_.params[k] = v;
  } else {
    // The bridge's copy only: the controller read its file at start (mavlink/mavlink_gains.hpp).
    gain->value = v;
    ++*gains_changed_;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s=%g set in bridge only (not live)", name, v);
    statustext(MAV_SEVERITY_NOTICE, buf, now);
    const std::string diff = gains_diff(p_.gains);
    set_health(heartbeat_t::STATE_OK,
               diff.empty() ? "bridging MAVLink"
                            : "bridging MAVLink; gains set, not applied (put in the control "
                              "config): " +
                                  diff);
  }
  send_param(k, now);
}

}  // namespace tiller::mavlink
