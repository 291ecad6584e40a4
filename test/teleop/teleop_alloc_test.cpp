// The teleop's hot path allocates nothing in steady state: js_event bytes -> parser -> state ->
// TeleopNode (shaping, debounce, publish of demand, velocity and raw state) and its ticks.
// operator new is counted for this whole binary.
#include <gtest/gtest.h>

#include "alloc_count.hpp"
#include "teleop_rig.hpp"

namespace tiller {
namespace {

class NullBus : public Bus {
 public:
  void publish(std::string_view, const std::uint8_t*, int) override { ++n; }
  long n = 0;
};

TEST(Allocation, StickEventsAndTicksAllocateNothing) {
  TeleopNode node(load_teleop_file(test::config_path("extreme3dpro_seed001.yaml")));
  NullBus bus;
  node.attach(&bus);
  JsEventParser parser;
  joystick_state_t s{};
  s.device = "alloc";
  const auto init = test::read_bytes(test::data_path("e3dp_positions.js"));
  parser.feed(init.data(), 18 * 8, s);
  s.connected = true;
  TimeUs now = 0, next_tick = 0;
  auto run = [&](int events) {
    for (int i = 0; i < events; ++i) {
      // Stick sweeps and twist; a gain-free button axis held now and then (past the debounce).
      JsEvent e[2] = {{0, static_cast<std::int16_t>((i * 997) % 65534 - 32767), kJsEventAxis, 1},
                      {0, static_cast<std::int16_t>((i * 331) % 65534 - 32767), kJsEventAxis, 2}};
      parser.feed(reinterpret_cast<const std::uint8_t*>(e), sizeof e, s);
      now += 2'000;
      while (next_tick <= now) node.tick(next_tick), next_tick += node.tick_period();
      node.feed(s, now);
    }
  };
  run(2000);  // warm-up: encode buffer, heartbeat strings and counters reach their size
  const long before = test::allocations();
  const long published = bus.n;
  run(10000);  // 20 s: 10,000 events, 1,000 ticks, 20 heartbeats
  EXPECT_EQ(test::allocations() - before, 0) << "heap allocations in steady-state teleop";
  EXPECT_GT(bus.n - published, 30000);
  node.attach(nullptr);
}

}  // namespace
}  // namespace tiller
