#include "nav/nav_params.hpp"

#include <optional>
#include <vector>

#include <tiller/gnss_fix_t.hpp>

#include "core/config.hpp"

namespace tiller::nav {

namespace {
using config::Range;
using config::Value;

constexpr Range kNonNegative{0, 1e12};

// Reads the optional section `key` with `read`, if it is there.
template <class F>
void section(const Value& root, std::string_view key, F&& read) {
  if (const std::optional<Value> s = root.find(key)) {
    if (!s->is_map()) s->fail("a map");
    read(*s);
  }
}
}  // namespace

NavParams load_nav_params(const Value& root) {
  NavParams p;
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {1, 1000});
  p.depth_source = root.choice_or("depth_source", "surface", {"surface", "pressure"}) == "surface"
                       ? DepthSource::kSurface
                       : DepthSource::kPressure;
  const Value datum = root.at("datum", "first_fix or {latitude_deg, longitude_deg, altitude_m}");
  if (datum.is_scalar()) {
    if (datum.as_string() != "first_fix")
      datum.fail("first_fix or a map {latitude_deg, longitude_deg, altitude_m}");
  } else if (datum.is_map()) {
    p.fixed_datum = true;
    // Plain degrees here (not angle_deg): GeographicLib takes degrees.
    p.datum_latitude_deg = datum.number("latitude_deg", {-90, 90});
    p.datum_longitude_deg = datum.number("longitude_deg", {-180, 180});
    p.datum_altitude_m = datum.number_or("altitude_m", 0.0, {-1e4, 1e5});
  } else {
    datum.fail("first_fix or a map {latitude_deg, longitude_deg, altitude_m}");
  }
  section(root, "recovery", [&](const Value& r) {
    p.recovery.rate_mps = r.number_or("rate_mps", p.recovery.rate_mps, {0, 100});
  });
  section(root, "datum_hold", [&](const Value& h) {
    p.datum_hold.hold_s = h.number_or("hold_s", p.datum_hold.hold_s, {0, 600});
    p.datum_hold.consistent_m = h.number_or("consistent_m", p.datum_hold.consistent_m, {0.1, 1000});
  });
  section(root, "gnss", [&](const Value& g) {
    auto& q = p.gnss;
    q.enabled = g.boolean_or("enabled", q.enabled);
    q.min_fix = g.choice_or("min_fix", "2d", {"2d", "3d"}) == "2d" ? gnss_fix_t::FIX_2D
                                                                   : gnss_fix_t::FIX_3D;
    q.default_std_m = g.number_or("default_std_m", q.default_std_m, {0.01, 1e3});
    q.min_std_m = g.number_or("min_std_m", q.min_std_m, {0.001, 1e3});
    q.rtk_fixed_std_m = g.number_or("rtk_fixed_std_m", q.rtk_fixed_std_m, {0.001, 1e3});
    q.rtk_float_std_m = g.number_or("rtk_float_std_m", q.rtk_float_std_m, {0.001, 1e3});
    q.use_velocity = g.boolean_or("use_velocity", q.use_velocity);
    q.velocity_std_mps = g.number_or("velocity_std_mps", q.velocity_std_mps, {0.001, 100});
    q.gate_chi2 = g.number_or("gate_chi2", q.gate_chi2, {0, 1e6});
    q.reset_after = static_cast<int>(g.integer_or("reset_after", q.reset_after, 1, 100000));
    q.timeout_s = g.number_or("timeout_s", q.timeout_s, {0.01, 3600});
    q.max_latency_s = g.number_or("max_latency_s", q.max_latency_s, {0, 10});
    q.latency_s = g.number_or("latency_s", q.latency_s, {0, 5});
  });
  section(root, "heading", [&](const Value& h) {
    auto& q = p.heading;
    q.declination = h.angle_deg_or("declination_deg", q.declination, {-180, 180});
    q.default_std = h.angle_deg_or("default_std_deg", q.default_std, {0.01, 180});
    q.gate_chi2 = h.number_or("gate_chi2", q.gate_chi2, {0, 1e6});
    q.reset_after = static_cast<int>(h.integer_or("reset_after", q.reset_after, 1, 100000));
  });
  section(root, "imu", [&](const Value& i) {
    auto& q = p.imu;
    q.timeout_s = i.number_or("timeout_s", q.timeout_s, {0.01, 60});
    q.default_attitude_std =
        i.angle_deg_or("default_attitude_std_deg", q.default_attitude_std, {0.001, 90});
    q.default_rate_std = i.number_or("default_rate_std", q.default_rate_std, {1e-6, 10});
    q.use_acceleration = i.boolean_or("use_acceleration", q.use_acceleration);
  });
  section(root, "depth", [&](const Value& d) {
    auto& q = p.depth;
    q.default_std_m = d.number_or("default_std_m", q.default_std_m, {1e-4, 100});
    q.gate_chi2 = d.number_or("gate_chi2", q.gate_chi2, {0, 1e6});
    q.timeout_s = d.number_or("timeout_s", q.timeout_s, {0.01, 60});
    q.reset_after = static_cast<int>(d.integer_or("reset_after", q.reset_after, 1, 100000));
  });
  section(root, "dvl", [&](const Value& d) {
    auto& q = p.dvl;
    q.enabled = d.boolean_or("enabled", q.enabled);
    q.max_fom_mps = d.number_or("max_fom_mps", q.max_fom_mps, {1e-4, 100});
    q.min_std_mps = d.number_or("min_std_mps", q.min_std_mps, {1e-5, 10});
    if (d.has("lever_arm_m")) {
      const std::vector<double> a = d.numbers("lever_arm_m", 3, {-10, 10});
      for (int i = 0; i < 3; ++i) q.lever_arm_m[i] = a[static_cast<std::size_t>(i)];
    }
    q.timeout_s = d.number_or("timeout_s", q.timeout_s, {0.01, 60});
    q.gate_chi2 = d.number_or("gate_chi2", q.gate_chi2, {0, 1e6});
    q.reset_after = static_cast<int>(d.integer_or("reset_after", q.reset_after, 1, 100000));
    q.initial_position_std_m =
        d.number_or("initial_position_std_m", q.initial_position_std_m, {0, 1e3});
  });
  section(root, "sway", [&](const Value& w) {
    auto& q = p.sway;
    q.enabled = w.boolean_or("enabled", q.enabled);
    q.std_mps = w.number_or("std_mps", q.std_mps, {1e-4, 10});
    q.rate_gain_s = w.number_or("rate_gain", q.rate_gain_s, {0, 100});
    q.min_speed_mps = w.number_or("min_speed_mps", q.min_speed_mps, {0, 20});
    q.gate_chi2 = w.number_or("gate_chi2", q.gate_chi2, {0, 1e6});
  });
  section(root, "process", [&](const Value& n) {
    auto& q = p.process;
    q.position = n.number_or("position", q.position, kNonNegative);
    q.velocity_horizontal = n.number_or("velocity_horizontal", q.velocity_horizontal, kNonNegative);
    q.velocity_vertical = n.number_or("velocity_vertical", q.velocity_vertical, kNonNegative);
    q.heading = n.number_or("heading", q.heading, kNonNegative);
    q.gyro_bias = n.number_or("gyro_bias", q.gyro_bias, kNonNegative);
    q.accel_bias = n.number_or("accel_bias", q.accel_bias, kNonNegative);
    q.current = n.number_or("current", q.current, kNonNegative);
  });
  section(root, "initial", [&](const Value& i) {
    p.initial_velocity_std_mps =
        i.number_or("velocity_std_mps", p.initial_velocity_std_mps, {0.001, 100});
    p.initial_gyro_bias_std = i.number_or("gyro_bias_std", p.initial_gyro_bias_std, {0, 10});
    p.initial_accel_bias_std = i.number_or("accel_bias_std", p.initial_accel_bias_std, {0, 100});
    p.initial_current_std_mps =
        i.number_or("current_std_mps", p.initial_current_std_mps, {0.001, 10});
  });
  section(root, "limits", [&](const Value& l) {
    auto& q = p.limits;
    q.position_std_m = l.number_or("position_std_m", q.position_std_m, Range::positive());
    q.velocity_std_mps = l.number_or("velocity_std_mps", q.velocity_std_mps, Range::positive());
    q.heading_std = l.angle_deg_or("heading_std_deg", q.heading_std, {0.001, 180});
    q.depth_std_m = l.number_or("depth_std_m", q.depth_std_m, Range::positive());
  });
  root.check_all_used();
  return p;
}

NavParams load_nav_file(const std::string& path) {
  return load_nav_params(Value::load_file(path));
}

}  // namespace tiller::nav
