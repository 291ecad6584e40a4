#include "control/rov_config.hpp"

#include <filesystem>

#include "control/rov_modes.hpp"

namespace tiller::control {

using config::Range;

namespace {

RovGains load_gains(const config::Value& v) {
  RovGains g;
  g.pilot = v.number_or("pilot", 1.0, {0, 1});
  g.kp = v.number_or("kp", 0, Range::at_least(0));
  g.ki = v.number_or("ki", 0, Range::at_least(0));
  g.kd = v.number_or("kd", 0, Range::at_least(0));
  g.ki_rate = v.number_or("ki_rate", 0, Range::at_least(0));
  g.i_limit = v.number_or("i_limit", 0, Range::at_least(0));
  g.max_output = v.number_or("max_output", 1e5, Range::positive());
  g.max_rate = v.number_or("max_rate", 0.5, Range::positive());
  g.capture_rate = v.number_or("capture_rate", 0.05, Range::at_least(0));
  g.capture_s = v.number_or("capture_s", 1.5, {0, 60});
  g.max_angle = v.number_or("max_angle", 0, {0, 3.2});
  g.max_accel = v.number_or("max_accel", 0, Range::at_least(0));
  return g;
}

// Absolute; else beside the config; else relative to one of its parent folders; else as given.
std::string resolve(const config::Value& key) {
  namespace fs = std::filesystem;
  const std::string rel = key.as_string();
  fs::path chosen;
  if (fs::path(rel).is_absolute()) {
    chosen = rel;
  } else {
    for (fs::path dir = fs::absolute(key.file()).parent_path(); chosen.empty();
         dir = dir.parent_path()) {
      if (fs::exists(dir / rel)) chosen = dir / rel;
      if (dir == dir.root_path() || dir.empty()) break;
    }
    if (chosen.empty()) chosen = rel;
  }
  if (!fs::exists(chosen))
    key.fail(
        "a vehicle file (absolute, or relative to this config's folder or one of its "
        "parents); not found: " +
        rel);
  return chosen.lexically_normal().string();
}

}  // namespace

RovControlParams load_rov_control(const config::Value& root) {
  const config::Value v = root.at("rov_control");
  RovControlParams p;
  p.vehicle_file = resolve(v.at("vehicle", "a vehicle file"));
  p.rate_hz = v.number_or("rate_hz", 50, {1, 1000});
  p.odometry_timeout_s = v.number_or("odometry_timeout_s", 0.5, {0.001, 60});
  p.input_timeout_s = v.number_or("input_timeout_s", 0.5, {0.001, 60});
  p.allocation_timeout_s = v.number_or("allocation_timeout_s", 0.5, {0.001, 60});
  p.blend_s = v.number_or("blend_s", 1.0, {0, 60});
  const std::string mode = v.choice_or("default_mode", "manual",
                                       {"manual", "stabilise", "depth_hold", "heading_hold", "rate",
                                        "surface", "position_hold", "depth_heading_hold"});
  p.default_mode = static_cast<std::int8_t>(rov_mode_from_name(mode));
  if (auto pos = v.find("position")) {
    p.require_position_covariance = pos->boolean_or("require_covariance", true);
    p.max_position_std_m = pos->number_or("max_std_m", 0.5, Range::positive());
    const std::string loss = pos->choice_or(
        "on_loss", "depth_heading_hold",
        {"depth_heading_hold", "depth_hold", "heading_hold", "stabilise", "surface", "manual"});
    p.position_loss_mode = static_cast<std::int8_t>(rov_mode_from_name(loss));
  }
  if (auto s = v.find("surface")) {
    p.surface_speed_m_s = s->number_or("speed_m_s", 0.25, Range::positive());
    p.surface_depth_m = s->number_or("depth_m", 0.15, Range::at_least(0));
  }
  if (auto a = v.find("axes")) {
    static const char* const names[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
    for (std::size_t i = 0; i < 6; ++i)
      if (auto g = a->find(names[i])) p.axes[i] = load_gains(*g);
  }
  return p;
}

RovControlParams load_rov_control_file(const std::string& path) {
  const auto root = config::Value::load_file(path);
  RovControlParams p = load_rov_control(root);
  if (auto d = root.find("description")) d->mark_used();
  root.check_all_used();  // a misspelt key is refused, naming it
  return p;
}

}  // namespace tiller::control
