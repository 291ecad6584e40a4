// Test rig for the ESC node: builds an EscNode from inline YAML (vehicle: test/esc/data/rov4.yaml
// unless the text says otherwise) over the sim backend or a fake I2C bus with device models,
// drives it tick by tick and captures everything it publishes.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "esc/esc_node.hpp"
#include "esc/fake/fake_i2c.hpp"
#include "runtime/channels.hpp"
#include "runtime/event.hpp"

namespace tiller::test {

inline std::string data_path(const std::string& f) {
  return std::string(TILLER_SOURCE_DIR) + "/test/esc/data/" + f;
}

// Parses YAML as if it were a file in test/esc/data (so `vehicle: rov4.yaml` resolves there).
inline esc::EscConfig parse_config(const std::string& yaml) {
  return esc::load_esc_config(config::Value::parse(yaml, data_path("inline.yaml")));
}

class Capture : public Bus {
 public:
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    events.push_back(
        Event{std::string(channel), now, std::vector<std::uint8_t>(data, data + size)});
  }
  template <class Msg>
  std::vector<Msg> all(const std::string& channel) const {
    std::vector<Msg> out;
    for (const auto& e : events) {
      if (e.channel != channel) continue;
      Msg m;
      if (decode(e, m)) out.push_back(m);
    }
    return out;
  }
  template <class Msg>
  Msg last(const std::string& channel) const {
    for (auto it = events.rbegin(); it != events.rend(); ++it) {
      Msg m;
      if (it->channel == channel && decode(*it, m)) return m;
    }
    ADD_FAILURE() << "nothing published on " << channel;
    return Msg{};
  }
  std::size_t count(const std::string& channel) const {
    std::size_t n = 0;
    for (const auto& e : events) n += e.channel == channel;
    return n;
  }
  std::vector<Event> events;
  TimeUs now = 0;
};

// The four ESC names of rov4.yaml in its order.
inline const std::vector<std::string> kRov4 = {"front_right", "front_left", "back_left",
                                               "back_right"};

struct Rig {
  Capture cap;
  i2c::FakeBus bus;
  std::map<int, std::unique_ptr<esc::fake::TgyEscModel>> tgy;
  std::unique_ptr<esc::fake::Pca9685Model> pca;
  std::unique_ptr<EscNode> node;
  TimeUs now = 0;

  // Sim backend (or any backend over the fake bus): `yaml` is the whole config.
  explicit Rig(const std::string& yaml, bool attach_models = true)
      : Rig(parse_config(yaml), attach_models) {}
  explicit Rig(const esc::EscConfig& cfg, bool attach_models = true) {
    if (attach_models && (cfg.backend == "i2c_tgy")) {
      for (const auto& e : cfg.escs) {
        auto m = std::make_unique<esc::fake::TgyEscModel>();
        bus.attach(static_cast<std::uint8_t>(e.address), m.get());
        tgy[e.address] = std::move(m);
      }
    }
    if (attach_models && cfg.backend == "pca9685") {
      pca = std::make_unique<esc::fake::Pca9685Model>();
      bus.attach(static_cast<std::uint8_t>(cfg.pca9685.address), pca.get());
    }
    node = std::make_unique<EscNode>(cfg.node, esc::make_backend(cfg, &bus));
    node->attach(&cap);
  }
  // Ticks at every period up to and including t; afterwards now == t.
  void run_until(TimeUs t) {
    for (; next_tick <= t; next_tick += node->tick_period()) {
      now = cap.now = next_tick;
      node->tick(next_tick);
    }
    now = cap.now = t;
  }
  TimeUs next_tick = 0;
  template <class Msg>
  void send(const std::string& ch, const Msg& m) {
    const Event e = encode(ch, now, m);
    cap.now = now;
    node->deliver(ch, e.data.data(), static_cast<int>(e.data.size()), now);
  }
  void command(const std::vector<double>& u, const std::vector<std::string>& names = kRov4,
               bool armed = true) {
    thruster_command_t m{};
    m.utime = now;
    m.armed = armed;
    m.n_thrusters = static_cast<std::int32_t>(u.size());
    m.names = names;
    m.command = u;
    m.arm_allowed = true;  // as the mixer says when its source in control is neutral
    send(channels::kThrusterCommand, m);
  }
  void arm(bool on, const std::string& source = "test") {
    arm_request_t r{};
    r.utime = now;
    r.arm = on;
    r.source = source;
    send(channels::kArmRequest, r);
  }
  esc_output_t output() const { return node->last_output(); }
};

// Configs used by several tests.
inline std::string sim_yaml(const std::string& extra = "", const std::string& esc_extra = "") {
  return "vehicle: rov4.yaml\nbackend: sim\n" + extra +
         "escs:\n"
         "  - {name: front_right" +
         esc_extra +
         "}\n"
         "  - {name: front_left" +
         esc_extra +
         "}\n"
         "  - {name: back_left" +
         esc_extra +
         "}\n"
         "  - {name: back_right" +
         esc_extra + "}\n";
}

inline std::string tgy_yaml(const std::string& extra = "", bool telemetry = true) {
  return "vehicle: rov4.yaml\nbackend: i2c_tgy\n" + extra +
         "i2c_tgy: {bus: /dev/i2c-1, telemetry: " + (telemetry ? "true" : "false") +
         ", motor_poles: 14}\n"
         "escs:\n"
         "  - {name: front_right, address: 0x29}\n"
         "  - {name: front_left, address: 0x2a}\n"
         "  - {name: back_left, address: 0x2b}\n"
         "  - {name: back_right, address: 0x2c}\n";
}

}  // namespace tiller::test
