// The controllers' gains as parameters (mavlink/mavlink_gains.hpp), read by lib/control's loaders.
#include "mavlink/mavlink_gains.hpp"

#include <cstdio>

#include "control/control_config.hpp"
#include "control/rov_config.hpp"
#include "core/config.hpp"

namespace tiller::mavlink {

namespace {

using config::Range;

void add(std::vector<GainParam>& out, const std::string& id, const std::string& key, double v,
         Range r) {
  out.push_back({id, key, v, v, r.min, r.max});
}

}  // namespace

std::vector<GainParam> load_gain_params(const std::string& file) {
  std::vector<GainParam> g;
  const auto root = config::Value::load_file(file);
  const Range zero = Range::at_least(0), pos = Range::positive();
  if (root.has("rov_control")) {
    const control::RovControlParams p = control::load_rov_control_file(file);
    static const char* const kAx[6] = {"SURGE", "SWAY", "HEAVE", "ROLL", "PITCH", "YAW"};
    static const char* const kKey[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
    for (std::size_t i = 0; i < 6; ++i) {
      const control::RovGains& a = p.axes[i];
      const std::string id = std::string("ROV_") + kAx[i] + "_";
      const std::string key = std::string("rov_control.axes.") + kKey[i] + ".";
      add(g, id + "PILOT", key + "pilot", a.pilot, {0, 1});
      add(g, id + "KP", key + "kp", a.kp, zero);
      add(g, id + "KI", key + "ki", a.ki, zero);
      add(g, id + "KD", key + "kd", a.kd, zero);
      add(g, id + "KIRATE", key + "ki_rate", a.ki_rate, zero);
      add(g, id + "ILIM", key + "i_limit", a.i_limit, zero);
      add(g, id + "MAXOUT", key + "max_output", a.max_output, pos);
    }
    return g;
  }
  const control::VelocityPidNodeParams v = control::load_velocity_pid_node_params(root);
  const control::StationKeepNodeParams s =
      control::load_station_keep_node_params(config::Value::load_file(file));
  const control::AxisGains* va[3] = {&v.pid.surge, &v.pid.sway, &v.pid.yaw};
  static const char* const kVa[3] = {"SURGE", "SWAY", "YAW"};
  static const char* const kVk[3] = {"surge", "sway", "yaw"};
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string id = std::string("VP_") + kVa[i] + "_";
    const std::string key = std::string("velocity_pid.") + kVk[i] + ".";
    add(g, id + "KDRAG", key + "k_drag", va[i]->k_drag, zero);
    add(g, id + "KDRAGQ", key + "k_drag_quad", va[i]->k_drag_quad, zero);
    add(g, id + "KERR", key + "k_error", va[i]->k_error, zero);
    add(g, id + "KI", key + "ki", va[i]->ki, zero);
    add(g, id + "ILIM", key + "i_limit", va[i]->i_limit, zero);
    add(g, id + "MAXOUT", key + "max_output", va[i]->max_output, pos);
  }
  add(g, "VP_HEADING_KP", "velocity_pid.heading_kp", v.pid.heading_kp, zero);
  add(g, "VP_MAX_YAW_RATE", "velocity_pid.max_yaw_rate", v.pid.max_yaw_rate, pos);
  const control::StationAxisGains* sa[3] = {&s.pid.x, &s.pid.y, &s.pid.yaw};
  static const char* const kSa[3] = {"X", "Y", "YAW"};
  static const char* const kSk[3] = {"x", "y", "yaw"};
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string id = std::string("SK_") + kSa[i] + "_";
    const std::string key = std::string("station_keep.") + kSk[i] + ".";
    add(g, id + "KP", key + "kp", sa[i]->kp, zero);
    add(g, id + "KI", key + "ki", sa[i]->ki, zero);
    add(g, id + "KD", key + "kd", sa[i]->kd, zero);
    add(g, id + "ILIM", key + "i_limit", sa[i]->i_limit, zero);
    add(g, id + "MAXOUT", key + "max_output", sa[i]->max_output, pos);
  }
  return g;
}

std::string gains_diff(const std::vector<GainParam>& gains) {
  std::string out;
  for (const GainParam& p : gains) {
    if (p.value == p.loaded) continue;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: %.9g (was %.9g)\n", p.key.c_str(), p.value, p.loaded);
    out += buf;
  }
  return out;
}

}  // namespace tiller::mavlink
