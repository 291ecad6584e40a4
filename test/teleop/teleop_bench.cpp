// Hot path of tiller-teleop: js_event bytes -> state -> TeleopNode -> encoded demand messages.
#include <benchmark/benchmark.h>

#include "teleop_rig.hpp"

namespace tiller {
namespace {

class NullBus : public Bus {
 public:
  void publish(std::string_view, const std::uint8_t*, int size) override { bytes += size; }
  std::int64_t bytes = 0;
};

void BM_StickEventToDemand(benchmark::State& st) {
  TeleopNode node(load_teleop_file(test::config_path("extreme3dpro_seed001.yaml")));
  NullBus bus;
  node.attach(&bus);
  JsEventParser parser;
  joystick_state_t s{};
  s.device = "bench";
  const auto init = test::read_bytes(test::data_path("e3dp_positions.js"));
  parser.feed(init.data(), 18 * 8, s);
  s.connected = true;
  TimeUs now = 1'000'000;
  node.feed(s, now);
  std::int16_t v = 0;
  for (auto _ : st) {
    JsEvent e{0, v, kJsEventAxis, 1};
    v = static_cast<std::int16_t>(v == -20000 ? -30000 : -20000);
    parser.feed(reinterpret_cast<const std::uint8_t*>(&e), sizeof e, s);
    now += 1000;
    node.feed(s, now);  // publishes TILLER_JOYSTICK, MANUAL_DEMAND and MANUAL_VELOCITY
  }
  benchmark::DoNotOptimize(bus.bytes);
  node.attach(nullptr);
}
BENCHMARK(BM_StickEventToDemand);

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
