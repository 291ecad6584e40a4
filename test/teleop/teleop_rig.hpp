// Test rig for TeleopNode: plays recorded js_event streams (test/data/joystick) into the node
// in device mode, ticking it on its grid like an executor, and collects what it publishes.
#pragma once

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/event.hpp"
#include "teleop/js_device.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller::test {

inline std::string data_path(const std::string& name) {
  return std::string(TILLER_SOURCE_DIR) + "/test/data/joystick/" + name;
}
inline std::string config_path(const std::string& name) {
  return std::string(TILLER_SOURCE_DIR) + "/config/teleop/" + name;
}

inline std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

class CollectBus : public Bus {
 public:
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    events.push_back(
        Event{std::string(channel), now, std::vector<std::uint8_t>(data, data + size)});
  }
  TimeUs now = 0;
  std::vector<Event> events;
};

class Rig {
 public:
  explicit Rig(TeleopParams p) : node(std::move(p)) {
    node.attach(&bus);
    state.device = "test";
    state.connected = false;
    state.n_axes = 0;
    state.n_buttons = 0;
    state.late_inits = 0;
  }
  ~Rig() { node.attach(nullptr); }

  // Sets the fed state to a connected Extreme-3D-Pro-like device (6 axes, 12 buttons, none
  // pressed) with these axis values; the next feed() delivers it.
  joystick_state_t& plug_in(std::vector<std::int16_t> axes = {0, 0, 0, 0, 0, 0}) {
    state.n_axes = static_cast<std::int32_t>(axes.size());
    state.axes = std::move(axes);
    state.n_buttons = 12;
    state.buttons.assign(12, false);
    state.connected = true;
    return state;
  }

  // Ticks due at or before t (ticks before deliveries at one instant).
  void run_until(TimeUs t) {
    while (next_tick <= t) {
      bus.now = next_tick;
      node.tick(next_tick);
      next_tick += node.tick_period();
    }
  }
  void feed(TimeUs t) {
    run_until(t);
    bus.now = t;
    node.feed(state, t);
  }
  // Plays a stream; event time_ms maps to t = time_ms * 1000 us. Events with one time are one read.
  void play(const std::string& file, TimeUs offset = 0) {
    const auto bytes = read_bytes(data_path(file));
    std::map<std::uint32_t, std::vector<std::uint8_t>> groups;
    for (std::size_t i = 0; i + 8 <= bytes.size(); i += 8) {
      JsEvent e;
      std::memcpy(&e, &bytes[i], 8);
      auto& g = groups[e.time_ms];
      g.insert(g.end(), bytes.begin() + static_cast<long>(i),
               bytes.begin() + static_cast<long>(i + 8));
    }
    for (const auto& [ms, g] : groups) {
      parser.feed(g.data(), g.size(), state);
      state.connected = true;
      feed(offset + static_cast<TimeUs>(ms) * 1000);
    }
  }
  void unplug(TimeUs t) {
    state.connected = false;
    std::fill(state.axes.begin(), state.axes.end(), 0);
    std::fill(state.buttons.begin(), state.buttons.end(), false);
    parser.reset();
    feed(t);
  }
  template <class Msg>
  std::vector<std::pair<TimeUs, Msg>> all(const std::string& channel) const {
    std::vector<std::pair<TimeUs, Msg>> out;
    for (const Event& e : bus.events) {
      if (e.channel != channel) continue;
      Msg m;
      if (decode(e, m)) out.emplace_back(e.time, m);
    }
    return out;
  }
  // The last demand published at or before t.
  manual_demand_t demand_at(TimeUs t) const {
    manual_demand_t last{};
    for (const auto& [time, m] : all<manual_demand_t>(channels::kManualDemand)) {
      if (time <= t) last = m;
    }
    return last;
  }

  TeleopNode node;
  CollectBus bus;
  TimeUs next_tick = 0;
  JsEventParser parser;
  joystick_state_t state;
};

}  // namespace tiller::test
