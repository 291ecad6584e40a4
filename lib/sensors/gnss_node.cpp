#include "sensors/gnss_node.hpp"

#include <gps.h>

#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/angles.hpp"
#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

namespace {
double or_zero(double v) {
  return std::isfinite(v) ? v : 0.0;
}
double seconds(const timespec_t& t) {
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
std::int8_t fix_type(int mode, int status) {
  // gpsd leaves status at 0 (STATUS_NO_FIX) in a TPV without "status": the mode decides.
  if (mode < MODE_2D) return gnss_fix_t::FIX_NONE;
  if (mode == MODE_2D) return gnss_fix_t::FIX_2D;
  switch (status) {
    case STATUS_DGPS_FIX:
      return gnss_fix_t::FIX_DGPS;
    case STATUS_RTK_FIX:
      return gnss_fix_t::FIX_RTK_FIXED;
    case STATUS_RTK_FLT:
      return gnss_fix_t::FIX_RTK_FLOAT;
    case STATUS_DR:
      return gnss_fix_t::FIX_DEAD_RECKONING;
    default:
      return gnss_fix_t::FIX_3D;
  }
}
}  // namespace

GnssParams load_gnss_params(const config::Value& root) {
  GnssParams p;
  p.host = root.string_or("gpsd_host", p.host);
  p.port = std::to_string(root.integer_or("gpsd_port", 2947, 1, 65535));
  p.channel = root.string_or("channel", p.channel);
  p.stale_after = from_seconds(root.number_or("stale_after_s", 2.0, {0.1, 3600}));
  p.reconnect_period = from_seconds(root.number_or("reconnect_period_s", 1.0, {0.01, 3600}));
  p.epoch_wait = from_seconds(root.number_or("epoch_wait_s", 0.5, {0.01, 10}));
  p.max_speed_mps = root.number_or("max_speed_mps", p.max_speed_mps, {0.1, 1000});
  p.jump_margin_m = root.number_or("jump_margin_m", p.jump_margin_m, {0, 1e4});
  p.time_jump_s = root.number_or("time_jump_s", p.time_jump_s, {0.01, 3600});
  p.accept_after = static_cast<int>(root.integer_or("accept_after", p.accept_after, 1, 1000));
  p.publish_heading = root.boolean_or("publish_heading", p.publish_heading);
  p.heading_channel = root.string_or("heading_channel", p.heading_channel);
  p.heading_std = root.number_or("heading_std_deg", 0.3, {0.01, 30.0}) * kPi / 180;
  root.check_all_used();
  return p;
}

GnssParams load_gnss_file(const std::string& path) {
  return load_gnss_params(config::Value::load_file(path));
}

GnssNode::GnssNode(const GnssParams& p) : Node("gnss", kUsPerSecond / 10), p_(p) {
  advertise<gnss_fix_t>(p.channel);
  fixes_ = &counter("fixes");
  no_fix_ = &counter("reports.no_fix");
  rejected_ = &counter("rejected.fix.range");
  repeated_ = &counter("reports.repeated_epoch");
  no_position_ = &counter("rejected.fix.no_position");
  jump_ = &counter("rejected.fix.jump");
  time_jump_ = &counter("rejected.fix.time_jump");
  incomplete_ = &counter("epochs.incomplete");
  jump_accepted_ = &counter("fix.jump_accepted");
  time_jump_accepted_ = &counter("fix.time_jump_accepted");
  msg_.satellites = -1;
  headings_ = &counter("headings");
  bad_heading_ = &counter("rejected.heading.range");
  if (p.publish_heading) advertise<heading_t>(p.heading_channel);
  heading_.reference = heading_t::REFERENCE_TRUE;
  heading_.source = heading_t::SOURCE_GNSS;
  heading_.variance = p.heading_std * p.heading_std;
  set_health(heartbeat_t::STATE_FAULT, link_problem_);
}

void GnssNode::set_link(const std::string& problem, TimeUs now) {
  link_problem_ = problem;
  on_tick(now);
}

void GnssNode::say_once(int kind, const std::string& what) {
  if (said_ & (1u << kind)) return;
  said_ |= 1u << kind;
  std::fprintf(stderr, "tiller-gnss: %s (counted in the heartbeat; said once)\n", what.c_str());
}

void GnssNode::on_attitude(const gps_data_t& d, TimeUs now) {
  const double deg = d.attitude.heading;
  if (!std::isfinite(deg) || deg < 0 || deg >= 360) {
    reject(*bad_heading_);
    say_once(7, "dropped a dual-antenna heading outside [0, 360) deg (rejected.heading.range)");
    return;
  }
  heading_.utime = now;
  heading_.heading = wrap_pi(deg * kPi / 180);
  if (heading_.device != d.dev.path) heading_.device = d.dev.path;
  publish(p_.heading_channel, heading_);
  ++*headings_;
}

void GnssNode::on_gps(const gps_data_t& d, TimeUs now) {
  if ((d.set & ATTITUDE_SET) && p_.publish_heading) {
    on_attitude(d, now);
    return;  // an ATT report carries nothing else (gps_data_t's union)
  }
  if (d.set & GST_SET) {
    gst_time_ = seconds(d.gst.utctime);
    gst_std_[0] = d.gst.lat_err_deviation;
    gst_std_[1] = d.gst.lon_err_deviation;
    gst_std_[2] = d.gst.alt_err_deviation;
    last_gst_ = now;
    // The GST of the held epoch: its accuracy, and maybe all it waited for.
    if (held_ && std::fabs(gst_time_ - static_cast<double>(msg_.gnss_utime) * 1e-6) < 1e-3 &&
        std::isfinite(gst_std_[0]) && std::isfinite(gst_std_[1])) {
      for (int i = 0; i < 3; ++i) msg_.position_std[i] = or_zero(gst_std_[i]);
      msg_.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
      if (complete(msg_)) flush(now);
    }
  }
  if (d.set & SATELLITE_SET) {
    msg_.satellites = static_cast<std::int16_t>(d.satellites_used);
    msg_.hdop = or_zero(d.dop.hdop);
  }
  if (!(d.set & MODE_SET)) return;  // not a TPV report
  const gps_fix_t& f = d.fix;
  const std::int64_t epoch =
      (d.set & TIME_SET) && f.time.tv_sec > 0
          ? static_cast<std::int64_t>(f.time.tv_sec) * 1'000'000 + f.time.tv_nsec / 1000
          : 0;
  // A report of another epoch: the held one has had all it will get.
  if (held_ && epoch != msg_.gnss_utime) flush(now);
  held_ = false;
  msg_.utime = now;
  msg_.gnss_utime = epoch;
  msg_.fix_type = fix_type(f.mode, f.status);
  if (msg_.fix_type != gnss_fix_t::FIX_NONE &&
      !(std::isfinite(f.latitude) && std::isfinite(f.longitude))) {
    reject(*no_position_);
    say_once(0,
             "a fix without a position (gpsd had no latitude / longitude: out of range or "
             "malformed) dropped");
    return;
  }
  // gpsd keeps mode 3 from GSA when the epoch's GGA was lost: no altitude, so a 2D fix.
  if (msg_.fix_type >= gnss_fix_t::FIX_3D && !std::isfinite(f.altHAE))
    msg_.fix_type = gnss_fix_t::FIX_2D;
  const bool has_fix = msg_.fix_type != gnss_fix_t::FIX_NONE;
  msg_.latitude = has_fix ? f.latitude : 0.0;
  msg_.longitude = has_fix ? f.longitude : 0.0;
  const bool has_alt = msg_.fix_type >= gnss_fix_t::FIX_3D;
  msg_.altitude = has_alt ? or_zero(f.altHAE) : 0.0;
  msg_.altitude_msl = has_alt ? or_zero(f.altMSL) : 0.0;
  const double t = seconds(f.time);
  // The GST of this very epoch only (gpsd's report of an epoch can come before its GST).
  if (has_fix && gst_time_ > 0 && std::fabs(gst_time_ - t) < 1e-3 && std::isfinite(gst_std_[0]) &&
      std::isfinite(gst_std_[1])) {
    for (int i = 0; i < 3; ++i) msg_.position_std[i] = or_zero(gst_std_[i]);
    msg_.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  } else if (has_fix && std::isfinite(f.epy) && std::isfinite(f.epx)) {
    msg_.position_std[0] = f.epy / 2;
    msg_.position_std[1] = f.epx / 2;
    msg_.position_std[2] = or_zero(f.epv) / 2;
    msg_.accuracy_source = gnss_fix_t::ACCURACY_DOP;
  } else {
    msg_.position_std[0] = msg_.position_std[1] = msg_.position_std[2] = 0;
    msg_.accuracy_source = gnss_fix_t::ACCURACY_NONE;
  }
  msg_.velocity_valid = has_fix && std::isfinite(f.speed) && std::isfinite(f.track);
  msg_.speed = msg_.velocity_valid ? f.speed : 0.0;
  msg_.course = msg_.velocity_valid ? wrap_pi(deg_to_rad(f.track)) : 0.0;
  msg_.device = d.dev.path;
  // One fix per epoch: gpsd sends a second TPV for an epoch while it learns a receiver's cycle
  // (and a client that does not clear `set` sees one per report); the estimator must not fuse
  // the same measurement twice.
  if (has_fix && epoch > 0 && epoch == last_epoch_) {
    ++*repeated_;
    return;
  }
  if (has_fix && epoch > 0 && !complete(msg_)) {
    held_ = true;
    held_since_ = now;
    return;
  }
  accept(now);
}

bool GnssNode::complete(const gnss_fix_t& f) const {
  const bool gst_expected = last_gst_ != INT64_MIN && f.utime - last_gst_ <= 2 * kUsPerSecond;
  return (f.velocity_valid || !expect_velocity_) &&
         (f.accuracy_source == gnss_fix_t::ACCURACY_RECEIVER || !gst_expected) &&
         (f.fix_type >= gnss_fix_t::FIX_3D || !expect_3d_);
}

void GnssNode::flush(TimeUs now) {
  if (!held_) return;
  held_ = false;
  if (!complete(msg_)) {
    ++*incomplete_;
    say_once(1,
             "an epoch without all its parts (a lost sentence: bad checksum or line noise) "
             "published as it came");
  }
  accept(now);
}

GnssNode::Jump GnssNode::jump(const Reference& r, const gnss_fix_t& f) const {
  if (!r.set) return Jump::kNone;
  if (f.gnss_utime > 0 && r.gnss_utime > 0) {
    const double receiver_step = static_cast<double>(f.gnss_utime - r.gnss_utime) * 1e-6;
    const double host_step = to_seconds(f.utime - r.received);
    if (receiver_step <= 0 || std::fabs(receiver_step - host_step) > p_.time_jump_s)
      return Jump::kTime;
  }
  double s = 0;
  GeographicLib::Geodesic::WGS84().Inverse(r.latitude, r.longitude, f.latitude, f.longitude, s);
  const double dt = f.gnss_utime > 0 && r.gnss_utime > 0
                        ? static_cast<double>(f.gnss_utime - r.gnss_utime) * 1e-6
                        : to_seconds(f.utime - r.received);
  return s > p_.max_speed_mps * std::max(dt, 0.0) + p_.jump_margin_m ? Jump::kPosition
                                                                     : Jump::kNone;
}

void GnssNode::accept(TimeUs now) {
  const bool has_fix = msg_.fix_type != gnss_fix_t::FIX_NONE;
  if (checks::check(msg_) != nullptr) {
    reject(*rejected_);
    say_once(2, "a fix out of range dropped");
    return;
  }
  if (has_fix) {
    const Reference here{true, msg_.gnss_utime, msg_.utime, msg_.latitude, msg_.longitude};
    const Jump j = jump(ref_, msg_);
    if (j != Jump::kNone) {
      // Consistent with the last refused fix (and it with the one before): a receiver that
      // really is there (or then) now, believed after accept_after of them.
      consistent_ = jump(candidate_, msg_) == Jump::kNone ? consistent_ + 1 : 1;
      candidate_ = here;
      if (consistent_ <= p_.accept_after) {
        if (j == Jump::kTime) {
          reject(*time_jump_);
          say_once(3, "a fix whose receiver time jumped against the host's clock dropped");
        } else {
          reject(*jump_);
          say_once(4, "a fix that moved faster than any vehicle can dropped");
        }
        return;
      }
      ++*(j == Jump::kTime ? time_jump_accepted_ : jump_accepted_);
      std::fprintf(stderr, "tiller-gnss: %d consistent fixes after a %s jump: believed\n",
                   consistent_, j == Jump::kTime ? "time" : "position");
    }
    consistent_ = 0;
    candidate_ = Reference{};
    ref_ = here;
    if (msg_.gnss_utime > 0) last_epoch_ = msg_.gnss_utime;
    expect_velocity_ = msg_.velocity_valid;
    expect_3d_ = msg_.fix_type >= gnss_fix_t::FIX_3D;
    ++*fixes_;
    last_fix_ = now;
  } else {
    ++*no_fix_;
  }
  last_had_fix_ = has_fix;
  publish(p_.channel, msg_);
  update_health(now);
}

void GnssNode::on_tick(TimeUs now) {
  if (held_ && now - held_since_ >= p_.epoch_wait) flush(now);
  update_health(now);
}

std::string GnssNode::summary() const {
  static const char* const kType[] = {"no fix",    "2D fix",    "3D fix",        "DGPS fix",
                                      "RTK float", "RTK fixed", "dead reckoning"};
  static const char* const kSource[] = {"unknown", "gpsd DOP model", "receiver GST"};
  char b[160];
  std::snprintf(b, sizeof b, ": %s, %d satellites, HDOP %.1f, %.1f m 1-sigma (%s)",
                kType[std::clamp<int>(msg_.fix_type, 0, 6)], msg_.satellites, msg_.hdop,
                std::max(msg_.position_std[0], msg_.position_std[1]),
                kSource[std::clamp<int>(msg_.accuracy_source, 0, 2)]);
  return "fix from gpsd at " + p_.host + ":" + p_.port + b;
}

void GnssNode::update_health(TimeUs now) {
  if (!link_problem_.empty()) {
    set_health(heartbeat_t::STATE_FAULT, link_problem_);
  } else if (last_fix_ == INT64_MIN || now - last_fix_ > p_.stale_after) {
    set_health(heartbeat_t::STATE_DEGRADED, "gpsd at " + p_.host + ":" + p_.port + ": no fix for " +
                                                std::to_string(p_.stale_after / 1000) + " ms");
  } else if (!last_had_fix_) {
    set_health(heartbeat_t::STATE_DEGRADED, "gpsd reports no fix");
  } else {
    set_health(heartbeat_t::STATE_OK, summary());
  }
}

}  // namespace tiller::sensors
