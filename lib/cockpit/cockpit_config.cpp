#include "cockpit/cockpit_config.hpp"

#include "teleop/teleop_params.hpp"

namespace tiller::cockpit {

CockpitConfig load_cockpit(const config::Value& root) {
  CockpitConfig c;
  ServerParams& s = c.server;
  s.listen = root.string_or("listen", s.listen);
  const auto colon = s.listen.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == s.listen.size()) {
    root.at("listen").fail("ADDRESS:PORT, e.g. 127.0.0.1:8088");
  }
  s.token_file = root.string_or("token_file", s.token_file);
  s.token = root.string_or("token", "");
  if (auto t = root.find("token"); t && s.token.size() < 16) {
    t->fail("a token of at least 16 characters (or leave it out: token_file)");
  }
  s.max_clients = static_cast<int>(root.integer_or("max_clients", s.max_clients, 1, 64));

  CockpitParams& p = c.node;
  p.period = from_hz(root.number_or("rate_hz", 20.0, {1.0, 100.0}));
  if (auto v = root.find("processes")) {
    if (!v->is_sequence()) v->fail("a list of process names, e.g. [sim, esc, mixer]");
    for (const auto& item : v->items()) p.processes.push_back(item.as_string());
  }
  p.station = root.string_or("station", "");
  if (p.station.size() > 64) root.at("station").fail("a station id of at most 64 characters");
  p.silent_after = from_seconds(root.number_or("silent_after_s", 3.0, {0.5, 60.0}));
  p.path_repeat = from_seconds(root.number_or("path_repeat_s", 1.0, {0.1, 60.0}));
  if (auto g = root.find("gamepad")) {
    p.gamepad_timeout = from_seconds(g->number_or("timeout_s", 0.5, {0.05, 1.0}));
    p.gamepad_gain = g->number_or("gain", 1.0, {0.0, 1.0});
    if (auto axes = g->find("axes")) {
      for (const auto& a : axes->items()) {
        GamepadAxis ga;
        ga.axis = static_cast<int>(a.integer("axis", 0, 15));
        const config::Value d = a.at("dof");
        ga.dof = dof_index(d.as_string());
        if (ga.dof < 0) d.fail("one of surge, sway, heave, roll, pitch, yaw (or x, y, z, k, m, n)");
        ga.sign = a.number_or("sign", 1.0, {-1.0, 1.0});
        if (ga.sign != 1.0 && ga.sign != -1.0) a.at("sign").fail("1 or -1");
        ga.deadzone = a.number_or("deadzone", 0.1, {0.0, 0.9});
        ga.expo = a.number_or("expo", 0.0, {0.0, 1.0});
        ga.gain = a.number_or("gain", 1.0, {0.0, 1.0});
        p.axes.push_back(ga);
      }
    }
  }
  if (auto t = root.find("thruster_test")) {
    p.thruster_test.max_command = t->number_or("max_command", 0.1, {0.0, 0.3});
    p.thruster_test.timeout = from_seconds(t->number_or("timeout_s", 0.5, {0.15, 2.0}));
  }
  if (auto g = root.find("start_gate")) {
    p.start_gate.enabled = true;
    p.start_gate.max_position_std_m =
        g->number_or("max_position_std_m", p.start_gate.max_position_std_m, {0.001, 1000.0});
    p.start_gate.settle_s = g->number_or("settle_s", 0.0, {0.0, 3600.0});
  }
  root.check_all_used();
  return c;
}

CockpitConfig load_cockpit_file(const std::string& path) {
  return load_cockpit(config::Value::load_file(path));
}

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::string item;
  for (char c : s + ",") {
    if (c == ',') {
      if (!item.empty()) out.push_back(item);
      item.clear();
    } else if (c != ' ') {
      item.push_back(c);
    }
  }
  return out;
}

}  // namespace tiller::cockpit
