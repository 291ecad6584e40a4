#include "control/control_config.hpp"

#include <tiller/controller_mode_t.hpp>

#include <filesystem>

#include "core/angles.hpp"
#include "core/config_files.hpp"

namespace tiller::control {

using config::Range;

AxisGains load_axis_gains(const config::Value& v) {
  AxisGains g;
  g.k_drag = v.number("k_drag", Range::at_least(0));
  g.k_drag_quad = v.number("k_drag_quad", Range::at_least(0));
  g.k_error = v.number("k_error", Range::at_least(0));
  g.ki = v.number("ki", Range::at_least(0));
  g.i_limit = v.number("i_limit", Range::at_least(0));
  g.max_output = v.number("max_output", Range::positive());
  return g;
}

static StationAxisGains load_station_gains(const config::Value& v) {
  StationAxisGains g;
  g.kp = v.number("kp", Range::at_least(0));
  g.ki = v.number("ki", Range::at_least(0));
  g.kd = v.number("kd", Range::at_least(0));
  g.i_limit = v.number("i_limit", Range::at_least(0));
  g.max_output = v.number("max_output", Range::positive());
  return g;
}

static ControllerNodeCommon load_common(const config::Value& v) {
  ControllerNodeCommon c;
  c.rate_hz = v.number("rate_hz", {0.1, 1000});
  c.odometry_timeout_s = v.number("odometry_timeout_s", {0.001, 60});
  c.on_stale = v.choice("on_stale_odometry", {"neutral", "hold"}) == "neutral"
                   ? StaleAction::kNeutral
                   : StaleAction::kHold;
  c.hold_s = v.number("hold_s", {0, 60});
  c.input_timeout_s = v.number("input_timeout_s", {0.001, 60});
  c.allocation_timeout_s = v.number("allocation_timeout_s", {0.001, 60});
  c.blend_s = v.number("blend_s", {0, 60});
  c.invalid_neutral_s = v.number_or("odometry_invalid_neutral_s", 60.0, {0, 3600});
  return c;
}

MunkModel vehicle_munk_model(const std::string& vehicle_file) {
  const auto root = config::Value::load_file(vehicle_file);
  root.mark_used();  // the mixer and the simulator check this file strictly; we read a part
  const config::Value d = root.at("dynamics", "the simulator's dynamics section");
  if (d.string("model") != "surface_3dof") d.at("model").fail("surface_3dof (a [u v r] hull)");
  // The matrix the simulator's Coriolis term uses (what makes the moment).
  const config::Value m =
      d.has("coriolis_mass_matrix") ? d.at("coriolis_mass_matrix") : d.at("mass_matrix");
  MunkModel h;
  h.m11 = m[0].as_numbers(3)[0];
  h.m22 = m[1].as_numbers(3)[1];
  h.m23 = m[1].as_numbers(3)[2];
  h.y_v = d.numbers("linear_damping", 3)[1];
  if (!(h.m11 > 0 && h.m22 > 0)) m.fail("positive surge and sway masses (kg, with added mass)");
  if (!(h.y_v > 0)) d.at("linear_damping").fail("a positive sway damping y_v (N s/m)");
  return h;
}

VelocityPidParams load_velocity_pid_params(const config::Value& v) {
  VelocityPidParams p;
  p.surge = load_axis_gains(v.at("surge"));
  p.sway = load_axis_gains(v.at("sway"));
  p.yaw = load_axis_gains(v.at("yaw"));
  p.heading_kp = v.number("heading_kp", Range::at_least(0));
  p.max_yaw_rate = v.number("max_yaw_rate", Range::positive());
  p.max_dt = v.number("max_dt_s", Range::positive());
  if (auto mc = v.find("munk_compensation")) {
    const double fraction = mc->number("fraction", {0, 2});
    const config::Value vf = mc->at("vehicle_file", "a vehicle file (config/vehicles/*.yaml)");
    const std::string file = config::resolve_near(vf.as_string(), v.file());
    if (!std::filesystem::exists(file)) {
      vf.fail(
          "a vehicle file (absolute, or relative to this file's folder or one of its parents); "
          "not found: " +
          vf.as_string());
    }
    p.munk = vehicle_munk_model(file);
    p.munk.fraction = fraction;
  }
  return p;
}

StationPidParams load_station_pid_params(const config::Value& v) {
  StationPidParams p;
  p.x = load_station_gains(v.at("x"));
  p.y = load_station_gains(v.at("y"));
  p.yaw = load_station_gains(v.at("yaw"));
  p.max_dt = v.number("max_dt_s", Range::positive());
  p.weathervane = v.boolean("weathervane");
  p.weathervane_min_force = v.number("weathervane_min_force", Range::at_least(0));
  p.weathervane_full_force =
      v.number("weathervane_full_force", Range::at_least(p.weathervane_min_force));
  p.reverse_radius = v.number("reverse_radius", Range::at_least(0));
  p.reverse_blend = v.number("reverse_blend_m", Range::at_least(0));
  p.heading_rate_limit = deg_to_rad(v.number_or("heading_rate_limit_dps", 0.0, {0, 3600}));
  return p;
}

std::int8_t parse_mode(const config::Value& v, const char* key) {
  const std::string m = v.choice(key, {"manual_open_loop", "manual_closed_loop", "waypointing"});
  if (m == "manual_open_loop") return controller_mode_t::MANUAL_OPEN_LOOP;
  if (m == "manual_closed_loop") return controller_mode_t::MANUAL_CLOSED_LOOP;
  return controller_mode_t::WAYPOINTING;
}

ArbiterParams load_arbiter_params(const config::Value& v) {
  ArbiterParams p;
  p.default_mode = parse_mode(v, "default_mode");
  p.station_radius = v.number("station_radius", Range::positive());
  p.hysteresis = v.number("hysteresis", Range::at_least(0));
  p.hold_position = v.boolean("hold_position");
  return p;
}

VelocityPidNodeParams load_velocity_pid_node_params(const config::Value& root) {
  VelocityPidNodeParams p;
  const auto v = root.at("velocity_pid");
  p.common = load_common(v);
  p.pid = load_velocity_pid_params(v);
  p.arbiter = load_arbiter_params(root.at("arbiter"));
  if (auto s = root.find("station_keep")) s->mark_used();
  if (auto s = root.find("description")) s->mark_used();
  root.check_all_used();
  return p;
}

StationKeepNodeParams load_station_keep_node_params(const config::Value& root) {
  StationKeepNodeParams p;
  const auto v = root.at("station_keep");
  p.common = load_common(v);
  p.pid = load_station_pid_params(v);
  if (auto s = root.find("velocity_pid")) s->mark_used();
  if (auto s = root.find("arbiter")) s->mark_used();
  if (auto s = root.find("description")) s->mark_used();
  root.check_all_used();
  return p;
}

}  // namespace tiller::control
