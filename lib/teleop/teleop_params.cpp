#include "teleop/teleop_params.hpp"

#include <tiller/controller_mode_t.hpp>

namespace tiller {

int dof_index(const std::string& name) {
  static const char* const names[6][2] = {{"surge", "x"}, {"sway", "y"},  {"heave", "z"},
                                          {"roll", "k"},  {"pitch", "m"}, {"yaw", "n"}};
  for (int i = 0; i < 6; ++i) {
    if (name == names[i][0] || name == names[i][1]) return i;
  }
  return -1;
}

namespace {

int read_dof(const config::Value& v, std::string_view key) {
  const config::Value d = v.at(key);
  const int i = dof_index(d.as_string());
  if (i < 0) d.fail("one of surge, sway, heave, roll, pitch, yaw (or x, y, z, k, m, n)");
  return i;
}

int button_or(const config::Value& b, std::string_view key) {
  return static_cast<int>(b.integer_or(key, -1, -1, 127));
}

}  // namespace

TeleopParams load_teleop(const config::Value& root) {
  TeleopParams p;
  const config::Value dev = root.at("device");
  p.device_path = dev.string_or("path", "");
  p.device_name = dev.string_or("name", "");
  if (p.device_path.empty() && p.device_name.empty()) dev.fail("a `path` or a `name`");

  p.period = from_hz(root.number_or("rate_hz", 50.0, {1.0, 1000.0}));
  p.reopen_period = from_seconds(root.number_or("reopen_period_s", 0.2, {0.01, 10.0}));
  p.publish_on_change = root.boolean_or("publish_on_change", true);
  p.debounce = from_seconds(root.number_or("debounce_ms", 30.0, {0.0, 500.0}) * 1e-3);

  double dz_default = 0.05, expo_default = 0.0;
  if (auto d = root.find("defaults")) {
    dz_default = d->number_or("deadzone", dz_default, {0.0, 0.9});
    expo_default = d->number_or("expo", expo_default, {0.0, 1.0});
  }

  const config::Value axes = root.at("axes");
  if (!axes.is_sequence() || axes.size() == 0) axes.fail("a non-empty list of axis mappings");
  for (const config::Value& a : axes.items()) {
    TeleopAxis m;
    m.axis = static_cast<int>(a.integer("axis", 0, 63));
    m.dof = read_dof(a, "dof");
    const double s = a.number("sign");
    if (s != 1.0 && s != -1.0) a.at("sign").fail("1 or -1");
    m.sign = s;
    m.trigger = a.boolean_or("trigger", false);
    m.deadzone = a.number_or("deadzone", dz_default, {0.0, 0.9});
    m.expo = a.number_or("expo", expo_default, {0.0, 1.0});
    m.gain = a.number_or("gain", 1.0, {0.0, 1.0});
    p.axes.push_back(m);
  }
  // Every button does one thing: a press runs every function mapped to it, so a button shared
  // by, say, gain_up and disarm would disarm in flight. Claims in order: the buttons section,
  // then button_axes; a repeat names the later key and the earlier one.
  struct Claim {
    int button;
    std::string key;
    config::Value where;
  };
  std::vector<Claim> claims;
  if (auto b = root.find("buttons")) {
    struct Slot {
      const char* key;
      int* field;
    };
    for (const Slot& s :
         {Slot{"arm", &p.buttons.arm}, Slot{"disarm", &p.buttons.disarm},
          Slot{"mode_open_loop", &p.buttons.mode_open_loop},
          Slot{"mode_closed_loop", &p.buttons.mode_closed_loop},
          Slot{"mode_autonomous", &p.buttons.mode_autonomous},
          Slot{"toggle_translation", &p.buttons.toggle_translation},
          Slot{"gain_up", &p.buttons.gain_up}, Slot{"gain_down", &p.buttons.gain_down},
          Slot{"takeover", &p.buttons.takeover}, Slot{"mode_stabilise", &p.buttons.mode_stabilise},
          Slot{"mode_depth_hold", &p.buttons.mode_depth_hold},
          Slot{"mode_heading_hold", &p.buttons.mode_heading_hold},
          Slot{"mode_rate", &p.buttons.mode_rate}, Slot{"mode_surface", &p.buttons.mode_surface},
          Slot{"mode_position_hold", &p.buttons.mode_position_hold}}) {
      *s.field = button_or(*b, s.key);
      if (*s.field >= 0)
        claims.push_back({*s.field, std::string("buttons.") + s.key, b->at(s.key)});
    }
  }
  if (auto ba = root.find("button_axes")) {
    std::size_t i = 0;
    for (const config::Value& a : ba->items()) {
      TeleopButtonAxis m;
      m.dof = read_dof(a, "dof");
      m.plus = static_cast<int>(a.integer("plus", 0, 127));
      m.minus = static_cast<int>(a.integer("minus", 0, 127));
      m.gain = a.number_or("gain", 1.0, {0.0, 1.0});
      p.button_axes.push_back(m);
      const std::string k = "button_axes[" + std::to_string(i++) + "].";
      claims.push_back({m.plus, k + "plus", a.at("plus")});
      claims.push_back({m.minus, k + "minus", a.at("minus")});
    }
  }
  for (std::size_t i = 0; i < claims.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (claims[j].button == claims[i].button) {
        claims[i].where.fail("a button not already used by " + claims[j].key + " (button " +
                             std::to_string(claims[i].button) + ")");
      }
    }
  }
  if (auto g = root.find("gain")) {
    p.gain_min = g->number_or("min", p.gain_min, {0.01, 1.0});
    p.gain_max = g->number_or("max", p.gain_max, {p.gain_min, 1.0});
    p.gain_initial = g->number_or("initial", p.gain_max, {p.gain_min, p.gain_max});
    p.gain_step = g->number_or("step", p.gain_step, {0.0, 1.0});
    p.gain_wrap = g->boolean_or("wrap", false);
  }
  if (auto c = root.find("closed_loop")) {
    const auto v = c->numbers("max_speed", 3, {0.0, 10.0});
    p.max_speed = {v[0], v[1], v[2]};
    p.max_yaw_rate = c->angle_deg("max_yaw_rate_deg", {0.0, 286.0});  // deg/s, up to 5 rad/s
    p.max_yaw_torque = c->number("max_yaw_torque", {0.0, 1e4});
    const std::string y = c->choice_or("yaw", "heading_hold", {"rate", "heading_hold", "torque"});
    p.yaw_mode = y == "rate"     ? YawMode::rate
                 : y == "torque" ? YawMode::torque
                                 : YawMode::heading_hold;
    p.odometry_timeout = from_seconds(c->number_or("odometry_timeout_s", 0.5, {0.01, 10.0}));
  }
  const std::string m =
      root.choice_or("initial_mode", "open_loop", {"open_loop", "closed_loop", "autonomous"});
  p.initial_mode = m == "open_loop"     ? controller_mode_t::MANUAL_OPEN_LOOP
                   : m == "closed_loop" ? controller_mode_t::MANUAL_CLOSED_LOOP
                                        : controller_mode_t::WAYPOINTING;
  p.initial_translation = root.boolean_or("initial_translation", false);
  p.station = root.string_or("station", "");
  if (p.station.size() > 64) root.at("station").fail("a station id of at most 64 characters");
  const double repeat_hz = root.number_or("mode_repeat_hz", 1.0, {0.0, 100.0});
  p.mode_repeat = repeat_hz > 0 ? from_hz(repeat_hz) : 0;
  root.check_all_used();
  return p;
}

TeleopParams load_teleop_file(const std::string& path) {
  return load_teleop(config::Value::load_file(path));
}

}  // namespace tiller
