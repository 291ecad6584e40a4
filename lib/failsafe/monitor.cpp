#include "failsafe/monitor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include <tiller/gnss_fix_t.hpp>
#include <tiller/vehicle_status_t.hpp>

namespace tiller::failsafe {

static_assert(static_cast<int>(Action::kNone) == vehicle_status_t::ACTION_NONE);
static_assert(static_cast<int>(Action::kWarn) == vehicle_status_t::ACTION_WARN);
static_assert(static_cast<int>(Action::kHold) == vehicle_status_t::ACTION_HOLD);
static_assert(static_cast<int>(Action::kReturn) == vehicle_status_t::ACTION_RETURN);
static_assert(static_cast<int>(Action::kSurface) == vehicle_status_t::ACTION_SURFACE);
static_assert(static_cast<int>(Action::kNeutral) == vehicle_status_t::ACTION_NEUTRAL);
static_assert(static_cast<int>(Action::kDisarm) == vehicle_status_t::ACTION_DISARM);
static_assert(static_cast<int>(Action::kRise) == vehicle_status_t::ACTION_RISE);
static_assert(kBatteryWarn == vehicle_status_t::EVENT_BATTERY_WARN);
static_assert(kBatteryCritical == vehicle_status_t::EVENT_BATTERY_CRITICAL);
static_assert(kLeak == vehicle_status_t::EVENT_LEAK);
static_assert(kGnssLost == vehicle_status_t::EVENT_GNSS_LOST);
static_assert(kGeofence == vehicle_status_t::EVENT_GEOFENCE);
static_assert(kDepthLimit == vehicle_status_t::EVENT_DEPTH_LIMIT);

namespace {

int severity(Action a) {
  switch (a) {
    case Action::kNone:
      return 0;
    case Action::kWarn:
      return 1;
    case Action::kHold:
      return 2;
    case Action::kReturn:
      return 3;
    case Action::kNeutral:
      return 4;
    case Action::kRise:
      return 5;
    case Action::kSurface:
      return 6;
    case Action::kDisarm:
      return 7;
  }
  return 7;
}

}  // namespace

double signed_distance(const std::vector<Point>& poly, Point p, double* nn, double* ne) {
  const std::size_t n = poly.size();
  if (n < 3) return std::numeric_limits<double>::infinity();
  double best = std::numeric_limits<double>::infinity();
  double bn = 0, be = 0;  // from the nearest boundary point to p
  bool inside = false;
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Point a = poly[j], b = poly[i];
    // Crossing number (ray toward +east).
    if ((b.north > p.north) != (a.north > p.north)) {
      const double e_at = a.east + (p.north - a.north) * (b.east - a.east) / (b.north - a.north);
      if (p.east < e_at) inside = !inside;
    }
    const double dn = b.north - a.north, de = b.east - a.east;
    const double len2 = dn * dn + de * de;
    double t = len2 > 0 ? ((p.north - a.north) * dn + (p.east - a.east) * de) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const double qn = p.north - (a.north + t * dn), qe = p.east - (a.east + t * de);
    const double d = std::hypot(qn, qe);
    if (d < best) {
      best = d;
      bn = qn;
      be = qe;
      if (d == 0) {  // on the edge: the outward normal of the edge (either winding)
        const double l = std::sqrt(len2);
        bn = l > 0 ? de / l : 0;
        be = l > 0 ? -dn / l : 0;
      }
    }
  }
  // Outward: from the boundary toward p when outside, away from p when inside.
  double on = bn, oe = be;
  const double l = std::hypot(on, oe);
  if (l > 0) {
    on /= l;
    oe /= l;
  }
  if (best == 0) {
    // The normal computed for the edge may point in; the polygon's centroid side says.
    double cn = 0, ce = 0;
    for (const Point& v : poly) {
      cn += v.north;
      ce += v.east;
    }
    cn /= static_cast<double>(n);
    ce /= static_cast<double>(n);
    if ((cn - p.north) * on + (ce - p.east) * oe > 0) {
      on = -on;
      oe = -oe;
    }
  } else if (inside) {
    on = -on;
    oe = -oe;
  }
  if (nn != nullptr) *nn = on;
  if (ne != nullptr) *ne = oe;
  return inside ? best : -best;
}

Monitor::Monitor(const MonitorParams& p) : p_(p) {}

void Monitor::update_below(Below& b, double v, double level, TimeUs now) {
  // Below the level starts the timer; only a reading above level + hysteresis stops it.
  if (v < level) {
    if (!b.below) {
      b.below = true;
      b.since = now;
    }
  } else if (v > level + p_.battery.hysteresis_v) {
    b.below = false;
  }
}

void Monitor::on_power(double voltage, TimeUs now) {
  have_power_ = true;
  power_at_ = now;
  voltage_ = voltage;
  if (!p_.battery.enabled) return;
  update_below(warn_, voltage, p_.battery.warn_v, now);
  update_below(critical_, voltage, p_.battery.critical_v, now);
}

void Monitor::on_leak(bool any_wet, TimeUs now) {
  have_leak_ = true;
  leak_at_ = now;
  if (any_wet && !wet_) wet_since_ = now;
  wet_ = any_wet;
}

bool Monitor::gnss_good(std::int8_t fix_type, double std_m) const {
  if (fix_type == gnss_fix_t::FIX_DEAD_RECKONING || fix_type < p_.gnss.min_fix) return false;
  return p_.gnss.max_std_m <= 0 || (std::isfinite(std_m) && std_m <= p_.gnss.max_std_m);
}

void Monitor::on_gnss(std::int8_t fix_type, double std_m, TimeUs now) {
  if (gnss_good(fix_type, std_m)) fix_good_at_ = now;
}

void Monitor::on_odometry(double n, double e, double d, double vn, double ve, bool valid,
                          bool depth_valid, TimeUs now) {
  if (valid) odom_valid_at_ = now;
  have_odom_ = true;
  odom_at_ = now;
  // An invalid position is no reading for the geofence: n_, e_ and the velocity stay the last
  // valid ones and the fence keeps its verdict (a hold stays a hold).
  position_valid_ = valid;
  if (valid) {
    n_ = n;
    e_ = e;
    vn_ = vn;
    ve_ = ve;
  }
  depth_valid_ = depth_valid;
  if (depth_valid) d_ = d;
}

void Monitor::on_operator_go(TimeUs) {
  fence_hold_ = false;
}

const Status& Monitor::step(TimeUs now) {
  if (start_ < 0) start_ = now;
  Status s;
  s.latched = status_.latched;
  Action act = Action::kNone;
  reason_[0] = '\0';
  auto raise = [&](std::int32_t bit, Action a, bool active, const char* fmt, auto... args) {
    if (active) s.active |= bit;
    if (!active && a == Action::kNone) return;
    if (severity(a) > severity(act) || (reason_[0] == '\0' && active)) {
      if (severity(a) > severity(act)) act = a;
      std::snprintf(reason_, sizeof reason_, fmt, args...);
    }
  };

  // Battery: latched once triggered.
  const BatteryParams& b = p_.battery;
  const bool power_fresh = have_power_ && now - power_at_ <= b.stale;
  if (b.enabled && power_fresh) {
    if (warn_.below && now - warn_.since >= b.trigger) s.latched |= kBatteryWarn;
    if (critical_.below && now - critical_.since >= b.trigger) s.latched |= kBatteryCritical;
  }
  if ((s.latched & kBatteryCritical) != 0) {
    s.latched |= kBatteryWarn;
    if (critical_at_ < 0) {
      critical_at_ = now;
      critical_voltage_ = voltage_;
    }
    const bool disarm = b.disarm_after >= 0 && now - critical_at_ >= b.disarm_after;
    raise(kBatteryCritical | kBatteryWarn, disarm ? Action::kDisarm : b.critical_action, true,
          disarm ? "battery critical (%.2f V < %.2f V), then %.0f s: disarmed"
                 : "battery critical: %.2f V < %.2f V (disarm after %.0f s)",
          critical_voltage_, b.critical_v, to_seconds(b.disarm_after));
  } else if ((s.latched & kBatteryWarn) != 0) {
    if (warn_at_ < 0) {
      warn_at_ = now;
      warn_voltage_ = voltage_;
    }
    raise(kBatteryWarn, Action::kWarn, true, "battery low: %.2f V < warning %.2f V", warn_voltage_,
          b.warn_v);
  }

  // Leak: latched.
  const LeakParams& l = p_.leak;
  if (l.enabled && have_leak_ && now - leak_at_ <= l.stale && wet_ && now - wet_since_ >= l.trigger)
    s.latched |= kLeak;
  if ((s.latched & kLeak) != 0) {
    if (leak_latched_at_ < 0) leak_latched_at_ = now;
    const bool disarm = l.action == Action::kDisarm ||
                        (l.disarm_after >= 0 && now - leak_latched_at_ >= l.disarm_after);
    raise(kLeak, disarm ? Action::kDisarm : l.action, true, "%s",
          disarm ? "leak: a probe is wet: disarmed" : "leak: a probe is wet");
  }

  // GNSS lost: not latched; hysteresis in time. The age of the older of the inputs used.
  const GnssParams& g = p_.gnss;
  if (g.enabled) {
    TimeUs last_ok = INT64_MAX;
    if (g.use_fix) last_ok = std::min(last_ok, fix_good_at_);
    if (g.use_odometry) last_ok = std::min(last_ok, odom_valid_at_);
    const TimeUs age = last_ok < 0 ? now - start_ : now - last_ok;
    const bool fix_ok = !g.use_fix || (fix_good_at_ >= 0 && now - fix_good_at_ <= g.stale);
    if (last_ok >= 0 && age <= g.stale) {
      if (good_since_ < 0) good_since_ = now;
      if (gnss_lost_ && now - good_since_ >= g.recover) gnss_lost_ = false;
    } else {
      good_since_ = -1;
    }
    if (age >= g.lost_after) gnss_lost_ = true;
    if (gnss_lost_) {
      s.latched |= kGnssLost;
      raise(kGnssLost, g.action, true,
            fix_ok ? "position lost: no valid odometry position for %.1f s"
                   : "GNSS lost: no good fix for %.1f s",
            to_seconds(g.lost_after));
    }
  }

  // Geofence and depth, on fresh odometry with a valid position / depth (stale or invalid: the
  // last verdict stays).
  const bool odom_fresh = have_odom_ && now - odom_at_ <= p_.odometry_stale;
  const GeofenceParams& f = p_.geofence;
  if (f.enabled && odom_fresh && position_valid_) {
    double on = 0, oe = 0;
    fence_d_ = signed_distance(f.polygon, {n_, e_}, &on, &oe);
    const double v_out = vn_ * on + ve_ * oe;
    if (v_out > kMinOutwardSpeed && fence_d_ - v_out * f.lookahead_s < f.margin_m)
      fence_hold_ = true;
    near_fence_ = fence_d_ < f.margin_m;
  }
  if (f.enabled && (near_fence_ || fence_hold_)) {
    s.latched |= kGeofence;
    raise(kGeofence, fence_hold_ ? f.action : Action::kNone, near_fence_,
          fence_d_ < 0 ? "geofence: %.1f m outside%s" : "geofence: %.1f m inside%s",
          std::fabs(fence_d_), fence_hold_ ? ", holding (a START or RESUME ends it)" : "");
  }
  const DepthParams& d = p_.depth;
  if (d.enabled && odom_fresh && depth_valid_) {
    if (d_ > d.limit_m) deep_ = true;
    if (d_ < d.limit_m - d.hysteresis_m) deep_ = false;
  }
  if (d.enabled && deep_) {
    s.latched |= kDepthLimit;
    raise(kDepthLimit, Action::kRise, true,
          depth_valid_ ? "depth %.1f m > limit %.1f m: rising"
                       : "depth unknown (last %.1f m > limit %.1f m): rising",
          d_, d.limit_m);
  }

  s.action = act;
  s.reason = reason_;
  s.changed = s.active != status_.active || s.latched != status_.latched ||
              s.action != status_.action || std::strcmp(reason_, last_reason_) != 0;
  std::memcpy(last_reason_, reason_, sizeof reason_);
  status_ = s;
  return status_;
}

}  // namespace tiller::failsafe
