// Steady-state ESC setups shared by the allocation test and the benchmark: an armed EscNode
// with N ESCs (4: rov4.yaml, 8: rov8.yaml) over the fake bus with device models, publishing to
// a bus that drops everything, and a pre-encoded thruster command.
#pragma once

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

class NullBus : public Bus {
 public:
  void publish(std::string_view, const std::uint8_t*, int) override {}
};

struct Steady {
  NullBus null;
  i2c::FakeBus bus;
  std::vector<std::unique_ptr<i2c::FakeDevice>> models;
  std::unique_ptr<EscNode> node;
  Event command, command_b;  // alternated, so every cycle's command is new
  bool flip = false;
  TimeUs now = 0;

  // backend: "i2c_tgy", "pca9685" or "sim"; n: 4 or 8 ESCs.
  Steady(const std::string& backend, int n) {
    const std::string dir = std::string(TILLER_SOURCE_DIR) + "/test/esc/data/";
    std::string yaml = "vehicle: " + std::string(n == 8 ? "rov8.yaml" : "rov4.yaml") +
                       "\nbackend: " + backend +
                       "\ndisarm_on_timeout: false\ncommand_timeout_ms: 10000\n"
                       "i2c_tgy: {bus: fake, telemetry: true}\n"
                       "pca9685: {address: 0x40}\nescs:\n";
    const std::vector<std::string> names =
        n == 8 ? std::vector<std::string>{"m0", "m1", "m2", "m3", "m4", "m5", "m6", "m7"}
               : std::vector<std::string>{"front_right", "front_left", "back_left", "back_right"};
    for (int i = 0; i < n; ++i) {
      yaml += "  - {name: " + names[static_cast<std::size_t>(i)] + ", " +
              (backend == "pca9685" ? "channel: " + std::to_string(i)
                                    : "address: " + std::to_string(0x29 + i)) +
              ", slew_per_s: 50}\n";
    }
    const auto cfg = esc::load_esc_config(config::Value::parse(yaml, dir + "steady.yaml"));
    if (backend == "i2c_tgy") {
      for (const auto& e : cfg.escs) {
        models.push_back(std::make_unique<esc::fake::TgyEscModel>());
        bus.attach(static_cast<std::uint8_t>(e.address), models.back().get());
      }
    } else if (backend == "pca9685") {
      models.push_back(std::make_unique<esc::fake::Pca9685Model>());
      bus.attach(0x40, models.back().get());
    }
    node = std::make_unique<EscNode>(cfg.node, esc::make_backend(cfg, &bus));
    node->attach(&null);
    thruster_command_t c{};
    c.armed = true;
    c.arm_allowed = true;
    c.n_thrusters = n;
    c.names = names;
    for (int i = 0; i < n; ++i) c.command.push_back(0.1 * (i % 5) - 0.2);
    command = encode(channels::kThrusterCommand, 0, c);
    c.command[0] += 0.05;  // a second command: the pilot's stick moves every cycle
    command_b = encode(channels::kThrusterCommand, 0, c);
    arm_request_t a{};
    a.arm = true;
    a.source = "bench";
    const Event arm = encode(channels::kArmRequest, 0, a);
    node->tick(0);
    node->deliver(channels::kArmRequest, arm.data.data(), static_cast<int>(arm.data.size()), 0);
  }
  // Writes `utime` into an encoded message in place (no allocation): LCM puts the 8-byte
  // fingerprint first and then the fields in order, big-endian; utime is the first field.
  static void set_utime(Event& e, TimeUs utime) {
    for (int i = 0; i < 8; ++i) {
      e.data[static_cast<std::size_t>(8 + i)] =
          static_cast<std::uint8_t>(static_cast<std::uint64_t>(utime) >> (56 - 8 * i));
    }
  }
  // One bus cycle (10 ms at 100 Hz): the node's ticks every tick_period (2 ms with
  // write_on_command), a changed command arriving mid-cycle and written at once, and the tick on
  // the cycle's grid writing every ESC again and reading one ESC's telemetry.
  void cycle() {
    const TimeUs cycle_period = from_hz(node->params().rate_hz);
    const TimeUs start = now;
    bool delivered = false;
    for (TimeUs t = start + node->tick_period(); t <= start + cycle_period;
         t += node->tick_period()) {
      if (!delivered && t > start + cycle_period / 2) {
        now = start + cycle_period / 2 + 500;
        Event& c = (flip = !flip) ? command : command_b;
        set_utime(c, now);  // fresh by its own time stamp too (the ESC refuses old utimes)
        node->deliver(c.channel, c.data.data(), static_cast<int>(c.data.size()), now);
        delivered = true;
      }
      now = t;
      node->tick(now);
    }
  }
};

}  // namespace tiller::test
