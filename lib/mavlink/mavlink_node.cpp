// MavlinkNode (mavlink/mavlink_node.hpp): its subscriptions, publications and counters, frames in
// (parse, signature, station) and out, the LCM state it reports and the telemetry streams.
#include "mavlink/mavlink_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tiller/arm_request_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/path_t.hpp>

#include "core/message_checks.hpp"
#include "mission/geo.hpp"
#include "runtime/channels.hpp"

namespace tiller::mavlink {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr TimeUs kHz(double hz) {
  return static_cast<TimeUs>(1e6 / hz);
}

// The streams and their default intervals.
struct DefaultStream {
  std::uint32_t msgid;
  TimeUs interval;
};
constexpr DefaultStream kDefaultStreams[] = {
    {MAVLINK_MSG_ID_HEARTBEAT, kHz(1)},      {MAVLINK_MSG_ID_SYS_STATUS, kHz(1)},
    {MAVLINK_MSG_ID_BATTERY_STATUS, kHz(1)}, {MAVLINK_MSG_ID_GLOBAL_POSITION_INT, kHz(5)},
    {MAVLINK_MSG_ID_ATTITUDE, kHz(10)},      {MAVLINK_MSG_ID_VFR_HUD, kHz(4)},
    {MAVLINK_MSG_ID_GPS_RAW_INT, kHz(1)},    {MAVLINK_MSG_ID_SERVO_OUTPUT_RAW, kHz(2)},
};

}  // namespace

MavlinkNode::MavlinkNode(MavlinkParams p)
    : Node("mavlink", p.period),
      p_(std::move(p)),
      writer_(p_.system_id, p_.component_id, p_.secret) {
  if (p_.secret) checker_.emplace(*p_.secret);
  for (const DefaultStream& d : kDefaultStreams) streams_.push_back({d.msgid, d.interval, 0});
  subscribe(channels::kArmState, &MavlinkNode::on_arm_state);
  subscribe(channels::kMode, &MavlinkNode::on_mode);
  subscribe(channels::kOdometry, &MavlinkNode::on_odometry);
  subscribe(channels::kDatum, &MavlinkNode::on_datum);
  subscribe(channels::kPower, &MavlinkNode::on_power);
  subscribe(channels::kGnss, &MavlinkNode::on_gnss);
  subscribe(channels::kEscOutput, &MavlinkNode::on_esc_output);
  subscribe(channels::kVehicleStatus, &MavlinkNode::on_vehicle_status);
  subscribe(channels::kPathProgress, &MavlinkNode::on_progress);
  advertise<manual_demand_t>(channels::kManualDemand);
  advertise<arm_request_t>(channels::kArmRequest);
  advertise<controller_mode_t>(channels::kMode);
  advertise<mission_command_t>(channels::kMissionCommand);
  advertise<path_t>(channels::kPath);
  advertise<path_speed_t>(channels::kPathSpeed);
  bad_crc_ = &counter("rejected.frame.crc");
  link_dropped_ = &counter("link.frames_dropped");
  v1_ = &counter("rejected.frame.mavlink1");
  bad_sig_ = &counter("rejected.frame.signature");
  replay_ = &counter("rejected.frame.replay");
  unsigned_ = &counter("rejected.frame.unsigned");
  other_station_ = &counter("rejected.frame.other_station");
  other_target_ = &counter("ignored.other_target");
  frames_ok_ = &counter("frames.accepted");
  bad_check_ = &counter("rejected.lcm.check");
  bad_manual_ = &counter("rejected.manual_control.value");
  pilot_timeout_ = &counter("pilot.lost.timeout");
  param_refused_ = &counter("rejected.param_set");
  mission_refused_ = &counter("rejected.mission");
  commands_ = &counter("commands.accepted");
  commands_refused_ = &counter("rejected.command");
  unknown_ = &counter("ignored.unhandled");
  gains_changed_ = &counter("params.gains_set");
  signing_refused_ = &counter("rejected.setup_signing");
  signing_set_ = &counter("signing.key_set");
  demand_.station = p_.station;
  demand_.valid = false;
  up_.items.reserve(256);
  set_health(heartbeat_t::STATE_OK, "bridging MAVLink");
}

TimeUs MavlinkNode::interval(std::uint32_t msgid) const {
  for (const Stream& s : streams_)
    if (s.msgid == msgid) return s.interval;
  return -1;
}

// ---------------------------------------------------------------- LCM in

void MavlinkNode::on_arm_state(const arm_state_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  const bool changed = m.armed != arm_.armed;
  arm_ = m;
  if (m.reason != last_arm_reason_) {
    last_arm_reason_ = m.reason;
    const bool refused = m.reason.find("refused") != std::string::npos;
    if (refused || changed)
      statustext(refused ? MAV_SEVERITY_WARNING : MAV_SEVERITY_INFO, m.reason, now);
  }
}

void MavlinkNode::on_mode(const controller_mode_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  mode_ = m.mode;
}

void MavlinkNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  odom_ = m;
  have_odom_ = true;
  if (seq_ && (m.valid & odometry_t::VALID_POSITION))
    fly(seq_->on_position(m.position[0], m.position[1], now), now);
}

void MavlinkNode::on_datum(const datum_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  datum_ = m;
  have_datum_ = true;
}

void MavlinkNode::on_power(const power_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  power_ = m;
  have_power_ = true;
}

void MavlinkNode::on_gnss(const gnss_fix_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  gnss_ = m;
  have_gnss_ = true;
}

void MavlinkNode::on_esc_output(const esc_output_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  n_servo_ = std::min<int>(m.n_channels, 16);
  double sum = 0;
  for (int i = 0; i < n_servo_; ++i) {
    const double u = m.normalized[static_cast<std::size_t>(i)];
    servo_[static_cast<std::size_t>(i)] = static_cast<std::uint16_t>(std::lround(1500 + 400 * u));
    sum += std::fabs(u);
  }
  throttle_ = n_servo_ > 0 ? sum / n_servo_ : 0.0;
}

void MavlinkNode::on_vehicle_status(const vehicle_status_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(*bad_check_);
    return;
  }
  if (m.active != failsafe_active_ || (m.active != 0 && m.reason != failsafe_reason_)) {
    if (m.active != 0)
      statustext(MAV_SEVERITY_CRITICAL, "failsafe: " + m.reason, now);
    else if (failsafe_active_ != 0)
      statustext(MAV_SEVERITY_NOTICE, "failsafe cleared", now);
  }
  failsafe_active_ = m.active;
  failsafe_reason_ = m.reason;
}

// ---------------------------------------------------------------- frames

void MavlinkNode::on_bytes(const std::uint8_t* data, std::size_t n, bool datagram, TimeUs now) {
  if (datagram) reader_.reset();
  for (std::size_t i = 0; i < n; ++i)
    if (reader_.feed(data[i])) on_frame(reader_.frame(), now);
  if (datagram) reader_.reset();
}

void MavlinkNode::on_frame(const FrameReader::Frame& f, TimeUs now) {
  switch (f.verdict) {
    case FrameVerdict::kBadCrc:
      reject(*bad_crc_);
      return;
    case FrameVerdict::kBadSignature:
      reject(*bad_sig_);
      return;
    case FrameVerdict::kMavlink1:
      reject(*v1_);
      return;
    case FrameVerdict::kOk:
      break;
  }
  if (f.is_signed && checker_) {
    const SignatureVerdict v = checker_->check(f.bytes, f.n, now);
    if (v == SignatureVerdict::kReplay || v == SignatureVerdict::kOld) {
      reject(*replay_);
      return;
    }
    if (v != SignatureVerdict::kOk) {
      reject(*bad_sig_);
      return;
    }
  } else if (p_.require_signed) {
    reject(*unsigned_);
    return;
  }
  ++*frames_ok_;
  frame_signed_ = f.is_signed && checker_;
  dispatch(*f.msg, now);
}

bool MavlinkNode::from_gcs(const mavlink_message_t& msg, TimeUs now) {
  if (msg.sysid == static_cast<std::uint8_t>(p_.params[kSysidMygcs])) return true;
  reject(*other_station_);
  statustext(MAV_SEVERITY_WARNING,
             "refused: station " + std::to_string(msg.sysid) + " is not in control (SYSID_MYGCS " +
                 std::to_string(static_cast<int>(p_.params[kSysidMygcs])) + ")",
             now);
  return false;
}

void MavlinkNode::dispatch(const mavlink_message_t& msg, TimeUs now) {
  switch (msg.msgid) {
    case MAVLINK_MSG_ID_HEARTBEAT:
      return;
    case MAVLINK_MSG_ID_COMMAND_LONG: {
      mavlink_command_long_t c;
      mavlink_msg_command_long_decode(&msg, &c);
      if (c.target_system != p_.system_id) {
        ++*other_target_;
        return;
      }
      const float prm[7] = {c.param1, c.param2, c.param3, c.param4, c.param5, c.param6, c.param7};
      on_command(msg, c.command, prm, now);
      return;
    }
    case MAVLINK_MSG_ID_COMMAND_INT: {
      mavlink_command_int_t c;
      mavlink_msg_command_int_decode(&msg, &c);
      if (c.target_system != p_.system_id) {
        ++*other_target_;
        return;
      }
      const float prm[7] = {
          c.param1, c.param2, c.param3, c.param4, static_cast<float>(c.x), static_cast<float>(c.y),
          c.z};
      on_command(msg, c.command, prm, now);
      return;
    }
    case MAVLINK_MSG_ID_SET_MODE: {
      mavlink_set_mode_t s;
      mavlink_msg_set_mode_decode(&msg, &s);
      if (s.target_system != p_.system_id) {
        ++*other_target_;
        return;
      }
      if (!from_gcs(msg, now)) return;
      const float prm[7] = {static_cast<float>(s.base_mode), static_cast<float>(s.custom_mode)};
      on_command(msg, MAV_CMD_DO_SET_MODE, prm, now);
      return;
    }
    case MAVLINK_MSG_ID_MANUAL_CONTROL:
      on_manual_control(msg, now);
      return;
    case MAVLINK_MSG_ID_SETUP_SIGNING:
      on_setup_signing(msg, now);
      return;
    case MAVLINK_MSG_ID_REQUEST_DATA_STREAM:
      on_data_stream(msg);
      return;
    case MAVLINK_MSG_ID_PARAM_REQUEST_LIST:
    case MAVLINK_MSG_ID_PARAM_REQUEST_READ:
    case MAVLINK_MSG_ID_PARAM_SET:
      on_param(msg, now);
      return;
    case MAVLINK_MSG_ID_MISSION_COUNT:
    case MAVLINK_MSG_ID_MISSION_ITEM_INT:
    case MAVLINK_MSG_ID_MISSION_REQUEST_LIST:
    case MAVLINK_MSG_ID_MISSION_REQUEST_INT:
    case MAVLINK_MSG_ID_MISSION_REQUEST:
    case MAVLINK_MSG_ID_MISSION_ACK:
    case MAVLINK_MSG_ID_MISSION_CLEAR_ALL:
    case MAVLINK_MSG_ID_MISSION_SET_CURRENT:
      on_mission(msg, now);
      return;
    default:
      ++*unknown_;
      return;
  }
}

void MavlinkNode::send(mavlink_message_t& msg, TimeUs now) {
  const std::size_t n = writer_.finish(msg, now, out_);
  if (sink_) sink_(out_, n);
}

void MavlinkNode::statustext(std::uint8_t severity, const std::string& text, TimeUs now) {
  char buf[MAVLINK_MSG_STATUSTEXT_FIELD_TEXT_LEN + 1] = {};
  std::strncpy(buf, text.c_str(), MAVLINK_MSG_STATUSTEXT_FIELD_TEXT_LEN);
  mavlink_message_t msg;
  mavlink_msg_statustext_pack_status(p_.system_id, p_.component_id, writer_.status(), &msg,
                                     severity, buf, 0, 0);
  send(msg, now);
}

// ---------------------------------------------------------------- telemetry

void MavlinkNode::on_tick(TimeUs now) {
  for (Stream& s : streams_) {
    if (s.interval <= 0 || now < s.next) continue;
    s.next = std::max(s.next + s.interval, now);
    send_stream(s.msgid, now);
  }
  if (pilot_rx_ >= 0 &&
      now - pilot_rx_ > static_cast<TimeUs>(p_.params[kManTimeout] * kUsPerSecond)) {
    pilot_rx_ = -1;
    centred_ = false;
    ++*pilot_timeout_;
    publish_demand(false, now);
    statustext(MAV_SEVERITY_WARNING, "MANUAL_CONTROL lost: neutral (centre the stick again)", now);
  }
  mission_tick(now);
  if (seq_) fly(seq_->on_tick(now), now);
}

void MavlinkNode::send_stream(std::uint32_t msgid, TimeUs now) {
  mavlink_message_t msg;
  const std::uint8_t sys = p_.system_id, comp = p_.component_id;
  mavlink_status_t* st = writer_.status();
  const std::uint32_t boot_ms = static_cast<std::uint32_t>((now / 1000) & 0xFFFFFFFF);
  const bool odom_pos = have_odom_ && (odom_.valid & odometry_t::VALID_POSITION);
  switch (msgid) {
    case MAVLINK_MSG_ID_HEARTBEAT: {
      std::uint8_t base = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED | MAV_MODE_FLAG_MANUAL_INPUT_ENABLED;
      if (arm_.armed) base |= MAV_MODE_FLAG_SAFETY_ARMED;
      if (mode_ == controller_mode_t::WAYPOINTING) base |= MAV_MODE_FLAG_AUTO_ENABLED;
      if (mode_ != controller_mode_t::MANUAL_OPEN_LOOP) base |= MAV_MODE_FLAG_STABILIZE_ENABLED;
      const std::uint8_t state = failsafe_active_ != 0 ? MAV_STATE_CRITICAL
                                 : arm_.armed          ? MAV_STATE_ACTIVE
                                                       : MAV_STATE_STANDBY;
      mavlink_msg_heartbeat_pack_status(
          sys, comp, st, &msg, p_.submarine ? MAV_TYPE_SUBMARINE : MAV_TYPE_SURFACE_BOAT,
          MAV_AUTOPILOT_GENERIC, base, static_cast<std::uint32_t>(mode_), state);
      break;
    }
    case MAVLINK_MSG_ID_SYS_STATUS: {
      const std::uint32_t sensors = MAV_SYS_STATUS_SENSOR_3D_GYRO | MAV_SYS_STATUS_SENSOR_GPS |
                                    MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS |
                                    MAV_SYS_STATUS_SENSOR_BATTERY;
      const std::uint16_t mv = have_power_ ? static_cast<std::uint16_t>(power_.voltage * 1000) : 0;
      const std::int16_t ca =
          have_power_
              ? static_cast<std::int16_t>(std::clamp(power_.current * 100, -32767.0, 32767.0))
              : -1;
      mavlink_msg_sys_status_pack_status(sys, comp, st, &msg, sensors, sensors,
                                         failsafe_active_ != 0 ? 0 : sensors, 0, mv, ca, -1, 0, 0,
                                         0, 0, 0, 0, 0, 0, 0);
      break;
    }
    case MAVLINK_MSG_ID_BATTERY_STATUS: {
      if (!have_power_) return;
      std::uint16_t cells[10];
      std::fill(std::begin(cells), std::end(cells), UINT16_MAX);
      cells[0] = static_cast<std::uint16_t>(std::min(power_.voltage * 1000, 65534.0));
      std::uint16_t ext[4] = {0, 0, 0, 0};
      mavlink_msg_battery_status_pack_status(
          sys, comp, st, &msg, 0, MAV_BATTERY_FUNCTION_ALL, MAV_BATTERY_TYPE_LION, INT16_MAX, cells,
          static_cast<std::int16_t>(std::clamp(power_.current * 100, -32767.0, 32767.0)),
          static_cast<std::int32_t>(power_.consumed_charge * 1000), -1, -1, 0,
          MAV_BATTERY_CHARGE_STATE_UNDEFINED, ext, 0, 0);
      break;
    }
    case MAVLINK_MSG_ID_GLOBAL_POSITION_INT: {
      if (!odom_pos || !have_datum_) return;
      const mission::LocalFrame lf({datum_.latitude, datum_.longitude, datum_.altitude});
      const mission::GeoPoint g = lf.to_geo(odom_.position[0], odom_.position[1]);
      const double c = std::cos(odom_.orientation[2]), s = std::sin(odom_.orientation[2]);
      const double vn = c * odom_.velocity[0] - s * odom_.velocity[1];
      const double ve = s * odom_.velocity[0] + c * odom_.velocity[1];
      double hdg = odom_.orientation[2] * 180 / kPi;
      if (hdg < 0) hdg += 360;
      mavlink_msg_global_position_int_pack_status(
          sys, comp, st, &msg, boot_ms, static_cast<std::int32_t>(std::lround(g.lat_deg * 1e7)),
          static_cast<std::int32_t>(std::lround(g.lon_deg * 1e7)),
          static_cast<std::int32_t>((datum_.altitude - odom_.position[2]) * 1000),
          static_cast<std::int32_t>(-odom_.position[2] * 1000), static_cast<std::int16_t>(vn * 100),
          static_cast<std::int16_t>(ve * 100), static_cast<std::int16_t>(odom_.velocity[2] * 100),
          static_cast<std::uint16_t>(std::lround(hdg * 100)) % 36000);
      break;
    }
    case MAVLINK_MSG_ID_ATTITUDE: {
      if (!have_odom_ || !(odom_.valid & odometry_t::VALID_ATTITUDE)) return;
      mavlink_msg_attitude_pack_status(
          sys, comp, st, &msg, boot_ms, static_cast<float>(odom_.orientation[0]),
          static_cast<float>(odom_.orientation[1]), static_cast<float>(odom_.orientation[2]),
          static_cast<float>(odom_.velocity[3]), static_cast<float>(odom_.velocity[4]),
          static_cast<float>(odom_.velocity[5]));
      break;
    }
    case MAVLINK_MSG_ID_VFR_HUD: {
      if (!have_odom_) return;
      const double speed = std::hypot(odom_.velocity[0], odom_.velocity[1]);
      double hdg = odom_.orientation[2] * 180 / kPi;
      if (hdg < 0) hdg += 360;
      mavlink_msg_vfr_hud_pack_status(
          sys, comp, st, &msg, static_cast<float>(speed), static_cast<float>(speed),
          static_cast<std::int16_t>(std::lround(hdg)) % 360,
          static_cast<std::uint16_t>(std::lround(throttle_ * 100)),
          static_cast<float>(-odom_.position[2]), static_cast<float>(-odom_.velocity[2]));
      break;
    }
    case MAVLINK_MSG_ID_GPS_RAW_INT: {
      if (!have_gnss_) return;
      static constexpr std::uint8_t kFix[] = {
          GPS_FIX_TYPE_NO_FIX,    GPS_FIX_TYPE_2D_FIX,    GPS_FIX_TYPE_3D_FIX, GPS_FIX_TYPE_DGPS,
          GPS_FIX_TYPE_RTK_FLOAT, GPS_FIX_TYPE_RTK_FIXED, GPS_FIX_TYPE_STATIC};
      const std::uint8_t fix = kFix[std::clamp<int>(gnss_.fix_type, 0, 6)];
      double cog = gnss_.course * 180 / kPi;
      if (cog < 0) cog += 360;
      mavlink_msg_gps_raw_int_pack_status(
          sys, comp, st, &msg, static_cast<std::uint64_t>(now), fix,
          static_cast<std::int32_t>(std::lround(gnss_.latitude * 1e7)),
          static_cast<std::int32_t>(std::lround(gnss_.longitude * 1e7)),
          static_cast<std::int32_t>(gnss_.altitude_msl * 1000),
          gnss_.hdop > 0 ? static_cast<std::uint16_t>(gnss_.hdop * 100) : UINT16_MAX, UINT16_MAX,
          gnss_.velocity_valid ? static_cast<std::uint16_t>(gnss_.speed * 100) : UINT16_MAX,
          gnss_.velocity_valid ? static_cast<std::uint16_t>(std::lround(cog * 100)) % 36000
                               : UINT16_MAX,
          gnss_.satellites < 0 ? 255
                               : static_cast<std::uint8_t>(std::min<int>(gnss_.satellites, 254)),
          static_cast<std::int32_t>(gnss_.altitude * 1000),
          static_cast<std::uint32_t>(gnss_.position_std[0] * 1000),
          static_cast<std::uint32_t>(gnss_.position_std[2] * 1000), 0, 0, 0);
      break;
    }
    case MAVLINK_MSG_ID_SERVO_OUTPUT_RAW: {
      std::array<std::uint16_t, 16> s{};
      for (int i = 0; i < n_servo_; ++i)
        s[static_cast<std::size_t>(i)] = servo_[static_cast<std::size_t>(i)];
      mavlink_msg_servo_output_raw_pack_status(
          sys, comp, st, &msg, static_cast<std::uint32_t>(now & 0xFFFFFFFF), 0, s[0], s[1], s[2],
          s[3], s[4], s[5], s[6], s[7], s[8], s[9], s[10], s[11], s[12], s[13], s[14], s[15]);
      break;
    }
    default:
      return;
  }
  send(msg, now);
}

void MavlinkNode::shutdown(TimeUs now) {
  if (pilot_rx_ >= 0 || demand_.valid) publish_demand(false, now);
}

}  // namespace tiller::mavlink
