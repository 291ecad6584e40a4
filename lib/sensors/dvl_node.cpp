#include "sensors/dvl_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

namespace {
// R = Rz(yaw) Ry(pitch) Rx(roll), row-major (Fossen's zyx convention).
std::array<double, 9> mounting_rotation(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll), sr = std::sin(roll);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  return {cy * cp,
          cy * sp * sr - sy * cr,
          cy * sp * cr + sy * sr,  //
          sy * cp,
          sy * sp * sr + cy * cr,
          sy * sp * cr - cy * sr,  //
          -sp,
          cp * sr,
          cp * cr};
}
}  // namespace

DvlParams load_dvl_params(const config::Value& root) {
  DvlParams p;
  p.host = root.string_or("host", p.host);
  if (p.host.empty()) root.at("host").fail("a host name or an IPv4 address");
  p.port = static_cast<int>(root.integer_or("port", p.port, 1, 65535));
  p.channel = root.string_or("channel", p.channel);
  if (const auto m = root.find("mounting")) {
    if (!m->is_map()) m->fail("a map with roll_deg, pitch_deg, yaw_deg");
    p.roll = m->angle_deg_or("roll_deg", 0, {-180, 180});
    p.pitch = m->angle_deg_or("pitch_deg", 0, {-90, 90});
    p.yaw = m->angle_deg_or("yaw_deg", 0, {-180, 180});
  }
  p.latency_s = root.number_or("latency_s", p.latency_s, {0, 5});
  p.timeout_s = root.number_or("timeout_s", p.timeout_s, {0.1, 3600});
  p.max_fom = root.number_or("max_fom", p.max_fom, config::Range::positive());
  p.reconnect_s = root.number_or("reconnect_s", p.reconnect_s, {0.01, 3600});
  p.connect_timeout_s = root.number_or("connect_timeout_s", p.connect_timeout_s, {0.1, 60});
  p.max_line = static_cast<std::size_t>(root.integer_or("max_line", 16384, 256, 1 << 20));
  root.check_all_used();
  return p;
}

DvlParams load_dvl_file(const std::string& path) {
  return load_dvl_params(config::Value::load_file(path));
}

DvlNode::DvlNode(const DvlParams& p)
    : Node("dvl", kUsPerSecond / 10),
      p_(p),
      r_(mounting_rotation(p.roll, p.pitch, p.yaw)),
      where_(p.host + ":" + std::to_string(p.port)) {
  advertise<dvl_t>(p.channel);
  velocity_ = &counter("lines.velocity");
  dead_reckoning_ = &counter("lines.dead_reckoning");
  ignored_ = &counter("lines.ignored");
  malformed_ = &counter("rejected.line.malformed");
  invalid_ = &counter("rejected.line.invalid");
  bad_velocity_ = &counter("rejected.velocity.invalid");
  fom_high_ = &counter("dvl.fom_high");
  lock_lost_ = &counter("dvl.lock_lost");
  lock_regained_ = &counter("dvl.lock_regained");
  connects_ = &counter("link.connects");
  disconnects_ = &counter("link.disconnects");
  overlong_ = &counter("lines.overlong");
  msg_.sensor = "dvl-a50@" + where_;
  msg_.altitude = -1;
  msg_.beams_valid = -1;
  status_.reserve(200);
  update_health(0);
}

void DvlNode::say_once(int kind, const char* what, const std::string& why) {
  if (said_ & (1u << kind)) return;
  said_ |= 1u << kind;
  std::fprintf(stderr, "tiller-dvl: %s: %s (counted in the heartbeat; said once)\n", what,
               why.c_str());
}

void DvlNode::feed(std::string_view line, TimeUs now) {
  DvlParsed d;
  try {
    d = parse_dvl_line(line);
  } catch (const std::exception& e) {  // the parser refuses with a reason; this is a backstop
    d.kind = DvlLine::kMalformed;
    d.why = e.what();
  }
  switch (d.kind) {
    case DvlLine::kVelocity:
      ++*velocity_;
      on_velocity(d.velocity, now);
      return;
    case DvlLine::kDeadReckoning:
      ++*dead_reckoning_;
      return;
    case DvlLine::kIgnored:
      ++*ignored_;
      return;
    case DvlLine::kMalformed:
      reject(*malformed_);
      say_once(0, "dropped a malformed line (rejected.line.malformed)", d.why);
      return;
    case DvlLine::kInvalid:
      reject(*invalid_);
      say_once(1, "dropped an invalid report (rejected.line.invalid)", d.why);
      return;
  }
}

void DvlNode::on_velocity(const DvlVelocity& v, TimeUs now) {
  const bool lock = v.bottom_lock && v.status == 0;
  msg_.utime = std::max<TimeUs>(0, now - from_seconds(p_.latency_s));
  msg_.bottom_lock = lock;
  msg_.status = v.status;
  msg_.fom = v.fom;
  msg_.beams_valid = static_cast<std::int8_t>(std::clamp(v.beams_valid, -1, 127));
  if (lock) {
    for (int i = 0; i < 3; ++i)
      msg_.velocity[i] =
          r_[3 * i] * v.velocity[0] + r_[3 * i + 1] * v.velocity[1] + r_[3 * i + 2] * v.velocity[2];
    std::array<double, 9> c{};
    if (v.has_covariance) {
      c = v.covariance;
    } else {
      c[0] = c[4] = c[8] = v.fom * v.fom;
    }
    std::array<double, 9> rc{};  // R C
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) rc[3 * i + j] += r_[3 * i + k] * c[3 * k + j];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += rc[3 * i + k] * r_[3 * j + k];  // (R C) R^T
        msg_.velocity_covariance[3 * i + j] = s;
      }
    }
    for (int i = 0; i < 3; ++i)  // exactly symmetric (rounding)
      for (int j = 0; j < i; ++j) {
        const double m =
            0.5 * (msg_.velocity_covariance[3 * i + j] + msg_.velocity_covariance[3 * j + i]);
        msg_.velocity_covariance[3 * i + j] = msg_.velocity_covariance[3 * j + i] = m;
      }
    msg_.altitude = v.altitude < 0 ? -1 : v.altitude;
  } else {
    for (double& x : msg_.velocity) x = 0;
    for (double& x : msg_.velocity_covariance) x = 0;
    msg_.altitude = -1;
  }
  if (checks::check(msg_) != nullptr) {
    reject(*bad_velocity_);
    say_once(2,
             "dropped a velocity report that fails the dvl_t contract (rejected.velocity.invalid)",
             checks::check(msg_));
    return;
  }
  if (lock && v.fom > p_.max_fom) ++*fom_high_;
  if (last_lock_ == 1 && !lock) ++*lock_lost_;
  if (last_lock_ == 0 && lock) ++*lock_regained_;
  last_lock_ = lock ? 1 : 0;
  last_altitude_ = v.altitude;
  last_status_ = v.status;
  have_report_ = true;
  since_ = now;
  publish(p_.channel, msg_);
  update_health(now);
}

void DvlNode::set_link(bool up, const std::string& why, TimeUs now) {
  if (up && !link_up_) {
    since_ = now;
    have_report_ = false;
  }
  link_up_ = up;
  link_why_ = why;
  // The client's reasons may start with the address the status names already.
  if (link_why_.rfind(where_ + ": ", 0) == 0) link_why_.erase(0, where_.size() + 2);
  update_health(now);
}

void DvlNode::count_link(std::int64_t connects, std::int64_t disconnects, std::int64_t overlong) {
  *connects_ = connects;
  *disconnects_ = disconnects;
  *overlong_ = overlong;
}

void DvlNode::update_health(TimeUs now) {
  if (!link_up_) {
    set_health(heartbeat_t::STATE_FAULT, "not connected to " + where_ + ": " + link_why_);
    return;
  }
  char b[200];
  const double quiet = to_seconds(now - since_);
  if (quiet >= p_.timeout_s) {
    std::snprintf(b, sizeof b, "no velocity report for %.1f s (connected to %s)", quiet,
                  where_.c_str());
    status_.assign(b);
    set_health(heartbeat_t::STATE_FAULT, status_);
    return;
  }
  if (!have_report_) {
    std::snprintf(b, sizeof b, "connected to %s, no velocity report yet", where_.c_str());
    status_.assign(b);
    set_health(heartbeat_t::STATE_DEGRADED, status_);
    return;
  }
  if (!msg_.bottom_lock) {
    if (last_altitude_ < 0) {
      std::snprintf(b, sizeof b, "no bottom lock (altitude none, status %d)", last_status_);
    } else {
      std::snprintf(b, sizeof b, "no bottom lock (altitude %.1f m, status %d)", last_altitude_,
                    last_status_);
    }
    status_.assign(b);
    set_health(heartbeat_t::STATE_DEGRADED, status_);
    return;
  }
  char extra[80] = "";
  if (msg_.fom > p_.max_fom)
    std::snprintf(extra, sizeof extra, " (above max_fom %.3f m/s)", p_.max_fom);
  if (msg_.altitude < 0) {
    std::snprintf(b, sizeof b, "bottom lock, altitude none, fom %.3f m/s%s", msg_.fom, extra);
  } else {
    std::snprintf(b, sizeof b, "bottom lock, altitude %.1f m, fom %.3f m/s%s", msg_.altitude,
                  msg_.fom, extra);
  }
  status_.assign(b);
  set_health(msg_.fom > p_.max_fom ? heartbeat_t::STATE_DEGRADED : heartbeat_t::STATE_OK, status_);
}

void DvlNode::on_tick(TimeUs now) {
  update_health(now);
}

}  // namespace tiller::sensors
