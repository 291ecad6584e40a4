#include "sensors/gnss_node.hpp"

#include <gps.h>

#include <cmath>

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
  root.check_all_used();
  return p;
}

GnssParams load_gnss_file(const std::string& path) {
  return load_gnss_params(config::Value::load_file(path));
}

GnssNode::GnssNode(const GnssParams& p) : Node("gnss", kUsPerSecond), p_(p) {
  advertise<gnss_fix_t>(p.channel);
  fixes_ = &counter("fixes");
  no_fix_ = &counter("reports.no_fix");
  rejected_ = &counter("rejected.fix.range");
  repeated_ = &counter("reports.repeated_epoch");
  msg_.satellites = -1;
  set_health(heartbeat_t::STATE_FAULT, link_problem_);
}

void GnssNode::set_link(const std::string& problem, TimeUs now) {
  link_problem_ = problem;
  on_tick(now);
}

void GnssNode::on_gps(const gps_data_t& d, TimeUs now) {
  if (d.set & GST_SET) {
    gst_time_ = seconds(d.gst.utctime);
    gst_std_[0] = d.gst.lat_err_deviation;
    gst_std_[1] = d.gst.lon_err_deviation;
    gst_std_[2] = d.gst.alt_err_deviation;
  }
  if (d.set & SATELLITE_SET) {
    msg_.satellites = static_cast<std::int16_t>(d.satellites_used);
    msg_.hdop = or_zero(d.dop.hdop);
  }
  if (!(d.set & MODE_SET)) return;  // not a TPV report
  const gps_fix_t& f = d.fix;
  msg_.utime = now;
  msg_.fix_type = fix_type(f.mode, f.status);
  const bool has_fix = msg_.fix_type != gnss_fix_t::FIX_NONE;
  msg_.gnss_utime =
      (d.set & TIME_SET) && f.time.tv_sec > 0
          ? static_cast<std::int64_t>(f.time.tv_sec) * 1'000'000 + f.time.tv_nsec / 1000
          : 0;
  msg_.latitude = has_fix ? or_zero(f.latitude) : 0.0;
  msg_.longitude = has_fix ? or_zero(f.longitude) : 0.0;
  const bool has_alt = msg_.fix_type >= gnss_fix_t::FIX_3D;
  msg_.altitude = has_alt ? or_zero(f.altHAE) : 0.0;
  msg_.altitude_msl = has_alt ? or_zero(f.altMSL) : 0.0;
  const double t = seconds(f.time);
  if (has_fix && gst_time_ > 0 && std::fabs(gst_time_ - t) < 0.5) {
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
  if (checks::check(msg_) != nullptr) {
    reject(*rejected_);
    return;
  }
  // One fix per epoch: gpsd sends a second TPV for an epoch while it learns a receiver's cycle
  // (and a client that does not clear `set` sees one per report); the estimator must not fuse
  // the same measurement twice.
  if (has_fix && msg_.gnss_utime > 0 && msg_.gnss_utime == last_epoch_) {
    ++*repeated_;
    return;
  }
  if (has_fix && msg_.gnss_utime > 0) last_epoch_ = msg_.gnss_utime;
  if (has_fix) {
    ++*fixes_;
    last_fix_ = now;
  } else {
    ++*no_fix_;
  }
  last_had_fix_ = has_fix;
  publish(p_.channel, msg_);
  on_tick(now);
}

void GnssNode::on_tick(TimeUs now) {
  if (!link_problem_.empty()) {
    set_health(heartbeat_t::STATE_FAULT, link_problem_);
  } else if (last_fix_ == INT64_MIN || now - last_fix_ > p_.stale_after) {
    set_health(heartbeat_t::STATE_DEGRADED, "gpsd at " + p_.host + ":" + p_.port + ": no fix for " +
                                                std::to_string(p_.stale_after / 1000) + " ms");
  } else if (!last_had_fix_) {
    set_health(heartbeat_t::STATE_DEGRADED, "gpsd reports no fix");
  } else {
    set_health(heartbeat_t::STATE_OK, "fix from gpsd at " + p_.host + ":" + p_.port);
  }
}

}  // namespace tiller::sensors
