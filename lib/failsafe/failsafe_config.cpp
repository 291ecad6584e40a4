#include "failsafe/failsafe_config.hpp"

#include <tiller/gnss_fix_t.hpp>

#include "core/config.hpp"

namespace tiller::failsafe {
namespace {

TimeUs seconds(const config::Value& v, const char* key, double fallback, double max = 3600) {
  return from_seconds(v.number_or(key, fallback, {0, max}));
}

Action action_of(const std::string& s) {
  if (s == "warn") return Action::kWarn;
  if (s == "hold") return Action::kHold;
  if (s == "surface") return Action::kSurface;
  if (s == "neutral") return Action::kNeutral;
  return Action::kDisarm;
}

// A polygon of [north, east] m pairs: at least 3, finite, no two consecutive equal.
std::vector<Point> polygon(const config::Value& v) {
  if (!v.is_sequence() || v.size() < 3 || v.size() > 256)
    v.fail("a list of 3 to 256 [north, east] points in m (local NED)");
  std::vector<Point> out;
  for (const config::Value& p : v.items()) {
    const auto ne = p.as_numbers(2, {-1e6, 1e6});
    out.push_back({ne[0], ne[1]});
    if (out.size() > 1 && out[out.size() - 2].north == ne[0] && out[out.size() - 2].east == ne[1])
      p.fail("a point other than the one before it");
  }
  double area2 = 0;
  for (std::size_t i = 0, j = out.size() - 1; i < out.size(); j = i++)
    area2 += out[j].north * out[i].east - out[i].north * out[j].east;
  if (area2 == 0) v.fail("a polygon with an area (these points are on one line)");
  return out;
}

}  // namespace

FailsafeNodeParams load_failsafe_params(const config::Value& root) {
  FailsafeNodeParams p;
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {1, 100});
  MonitorParams& m = p.monitor;
  m.odometry_stale = seconds(root, "odometry_stale_s", 1.0, 60);
  if (auto b = root.find("battery")) {
    BatteryParams& r = m.battery;
    r.enabled = true;
    r.warn_v = b->number("warn_v", {0, 100});
    r.critical_v = b->number("critical_v", {0, 100});
    if (!(r.critical_v < r.warn_v))
      b->at("critical_v").fail("a voltage below warn_v (" + std::to_string(r.warn_v) + " V)");
    r.hysteresis_v = b->number_or("hysteresis_v", r.hysteresis_v, {0, 10});
    r.trigger = seconds(*b, "trigger_s", 2.0, 600);
    r.critical_action = action_of(
        b->choice_or("critical_action", "hold", {"hold", "surface", "neutral", "disarm"}));
    r.disarm_after = b->has("disarm_after_s") ? seconds(*b, "disarm_after_s", 60, 86400) : -1;
    r.stale = seconds(*b, "stale_s", 2.0, 600);
    r.resistance_ohm = b->number_or("resistance_ohm", 0.0, {0, 1});
  }
  if (auto l = root.find("leak")) {
    LeakParams& r = m.leak;
    r.enabled = true;
    r.action = action_of(l->choice("action", {"surface", "disarm", "hold", "neutral", "warn"}));
    r.trigger = seconds(*l, "trigger_s", 0.0, 600);
    r.disarm_after = l->has("disarm_after_s") ? seconds(*l, "disarm_after_s", 60, 86400) : -1;
    r.stale = seconds(*l, "stale_s", 2.0, 600);
  }
  if (auto g = root.find("gnss")) {
    GnssParams& r = m.gnss;
    r.enabled = true;
    r.lost_after = from_seconds(g->number("lost_after_s", {0.1, 3600}));
    r.recover = seconds(*g, "recover_s", 2.0);
    const std::string fix =
        g->choice_or("min_fix", "2d", {"2d", "3d", "dgps", "rtk_float", "rtk_fixed"});
    r.min_fix = fix == "2d"          ? gnss_fix_t::FIX_2D
                : fix == "3d"        ? gnss_fix_t::FIX_3D
                : fix == "dgps"      ? gnss_fix_t::FIX_DGPS
                : fix == "rtk_float" ? gnss_fix_t::FIX_RTK_FLOAT
                                     : gnss_fix_t::FIX_RTK_FIXED;
    r.max_std_m = g->number_or("max_std_m", 0.0, {0, 1e5});
    r.stale = seconds(*g, "stale_s", 1.0, 600);
    r.use_fix = g->boolean_or("use_fix", true);
    r.use_odometry = g->boolean_or("use_odometry", false);
    if (!r.use_fix && !r.use_odometry)
      g->at("use_odometry").fail("true when use_fix is false (the rule needs an input)");
    r.action = action_of(g->choice_or("action", "hold", {"hold", "neutral", "warn"}));
  }
  if (auto f = root.find("geofence")) {
    GeofenceParams& r = m.geofence;
    r.enabled = true;
    r.polygon = polygon(f->at("polygon", "a list of [north, east] points in m"));
    r.margin_m = f->number_or("margin_m", r.margin_m, {0, 1e4});
    r.lookahead_s = f->number_or("lookahead_s", r.lookahead_s, {0, 60});
    r.action = action_of(f->choice_or("action", "hold", {"hold", "neutral"}));
  }
  if (auto d = root.find("depth_limit")) {
    DepthParams& r = m.depth;
    r.enabled = true;
    r.limit_m = d->number("limit_m", {0, 1e4});
    r.hysteresis_m = d->number_or("hysteresis_m", r.hysteresis_m, {0, 100});
    p.rise_thrust_n = d->number_or("rise_thrust_n", p.rise_thrust_n, {1e-3, 1e5});
  }
  p.surface_thrust_n = root.number_or("surface_thrust_n", p.surface_thrust_n, {1e-3, 1e5});
  p.surface_depth_m = root.number_or("surface_depth_m", p.surface_depth_m, {0, 100});
  root.check_all_used();
  return p;
}

FailsafeNodeParams load_failsafe_file(const std::string& path) {
  return load_failsafe_params(config::Value::load_file(path));
}

}  // namespace tiller::failsafe
