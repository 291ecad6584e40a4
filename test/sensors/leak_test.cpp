// Leak probes (sensors/leak_node.hpp) through the fake GPIO lines: active-high and active-low
// probes, wet at once and dry only after dry_after_s, a missing chip or a failing line read wet
// (fail safe) and are asked for again, bias passed on, strict config.
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <vector>

#include <tiller/heartbeat_t.hpp>
#include <tiller/leak_t.hpp>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "runtime/node.hpp"
#include "sensors/gpio.hpp"
#include "sensors/leak_node.hpp"

namespace tiller::sensors {
namespace {

struct Capture : Bus {
  std::vector<leak_t> readings;
  heartbeat_t hb;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    if (ch == "TILLER_LEAK") {
      leak_t m;
      if (m.decode(d, 0, n) == n) readings.push_back(m);
    } else if (ch == "TILLER_HEARTBEAT_LEAK") {
      hb.decode(d, 0, n);
    }
  }
};

LeakParams two_probes() {
  return load_leak_params(config::Value::parse(
      "probes:\n"
      "  - {name: main_tube, chip: gpiochip0, line: 27, active: high, bias: pull_down}\n"
      "  - {name: battery_tube, chip: gpiochip0, line: 22, active: low, bias: pull_up}\n"
      "rate_hz: 10\ndry_after_s: 2.0\n",
      "leak.yaml"));
}

struct Rig {
  FakeGpio gpio;
  LeakParams p = two_probes();
  Capture out;
  Rig() {
    gpio.line("gpiochip0", 27).level = 0;  // active high: dry
    gpio.line("gpiochip0", 22).level = 1;  // active low: dry
  }
  void run(LeakNode& n, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += n.tick_period()) n.tick(t);
  }
};

TEST(LeakNode, DryProbesReadDry) {
  Rig r;
  LeakNode n(r.p, r.gpio);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  ASSERT_EQ(r.out.readings.size(), 11u);
  const leak_t& m = r.out.readings.front();  // dry from the first reading
  ASSERT_EQ(m.n_probes, 2);
  EXPECT_EQ(m.names[0], "main_tube");
  EXPECT_EQ(m.names[1], "battery_tube");
  EXPECT_FALSE(m.wet[0]);
  EXPECT_FALSE(m.wet[1]);
  EXPECT_TRUE(m.readable[0]);
  EXPECT_FALSE(m.any_wet);
  EXPECT_EQ(checks::check(m), nullptr);
  EXPECT_EQ(r.gpio.line("gpiochip0", 27).bias, Bias::pull_down);
  EXPECT_EQ(r.gpio.line("gpiochip0", 22).bias, Bias::pull_up);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK);
  EXPECT_EQ(r.out.hb.status, "2 probes dry");
}

TEST(LeakNode, WetAtOnceDryOnlyAfterDryAfterWithoutABreak) {
  Rig r;
  LeakNode n(r.p, r.gpio);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  r.gpio.line("gpiochip0", 22).level = 0;  // the active-low probe goes wet
  n.tick(600'000);
  EXPECT_TRUE(r.out.readings.back().wet[1]);
  EXPECT_FALSE(r.out.readings.back().wet[0]);
  EXPECT_TRUE(r.out.readings.back().any_wet);
  EXPECT_EQ(n.counter_value("wet_events"), 1);
  r.gpio.line("gpiochip0", 22).level = 1;  // dry again at 0.7 s ...
  r.run(n, 700'000, 1'500'000);
  EXPECT_TRUE(r.out.readings.back().wet[1]);  // ... still wet: 0.9 s < 2 s
  r.gpio.line("gpiochip0", 22).level = 0;     // a drip at 1.6 s starts the 2 s again
  n.tick(1'600'000);
  r.gpio.line("gpiochip0", 22).level = 1;
  r.run(n, 1'700'000, 3'500'000);
  EXPECT_TRUE(r.out.readings.back().wet[1]);  // 3.5 s - 1.6 s = 1.9 s
  EXPECT_EQ(r.out.hb.status, "LEAK: battery_tube wet");
  n.tick(3'600'000);  // 2.0 s of dry reads
  EXPECT_FALSE(r.out.readings.back().wet[1]);
  EXPECT_FALSE(r.out.readings.back().any_wet);
  EXPECT_EQ(n.counter_value("wet_events"), 1);  // one leak, not one per drip
}

TEST(LeakNode, WetAtStartIsWetAtTheFirstReading) {
  Rig r;
  r.gpio.line("gpiochip0", 27).level = 1;
  LeakNode n(r.p, r.gpio);
  n.attach(&r.out);
  n.tick(0);
  EXPECT_TRUE(r.out.readings.back().wet[0]);
  EXPECT_TRUE(r.out.readings.back().readable[0]);
}

TEST(LeakNode, MissingChipReadsWetNamesTheLineAndIsRetried) {
  Rig r;
  r.gpio.missing_chip = true;
  LeakNode n(r.p, r.gpio);
  n.attach(&r.out);
  r.run(n, 0, 2 * kUsPerSecond);
  const leak_t& m = r.out.readings.back();
  EXPECT_FALSE(m.readable[0]);
  EXPECT_TRUE(m.wet[0]);  // fail safe
  EXPECT_TRUE(m.any_wet);
  EXPECT_EQ(checks::check(m), nullptr);
  EXPECT_EQ(n.counter_value("gpio.request_failures"), 6);  // 2 probes at 0, 1, 2 s
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(r.out.hb.status.find("probe main_tube (gpiochip0 line 27, active high): cannot open "
                                 "GPIO chip gpiochip0"),
            std::string::npos)
      << r.out.hb.status;
  r.gpio.missing_chip = false;  // the chip appears: both lines dry from the next request
  r.run(n, 2'100'000, 3 * kUsPerSecond);
  EXPECT_TRUE(r.out.readings.back().readable[0]);
  EXPECT_FALSE(r.out.readings.back().any_wet);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK);
}

TEST(LeakNode, AReadErrorReadsWetAndTheLineIsRequestedAgain) {
  Rig r;
  LeakNode n(r.p, r.gpio);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  r.gpio.line("gpiochip0", 27).read_error = EIO;
  n.tick(600'000);
  EXPECT_FALSE(r.out.readings.back().readable[0]);
  EXPECT_TRUE(r.out.readings.back().wet[0]);
  EXPECT_FALSE(r.out.readings.back().wet[1]);
  EXPECT_EQ(n.counter_value("gpio.read_errors"), 1);
  EXPECT_FALSE(r.gpio.line("gpiochip0", 27).requested);  // given back
  r.gpio.line("gpiochip0", 27).read_error = 0;
  r.run(n, 700'000, 1'600'000);  // asked for again at 1.6 s
  EXPECT_TRUE(r.out.readings.back().readable[0]);
  EXPECT_FALSE(r.out.readings.back().wet[0]);
}

TEST(LeakNode, GivesItsLinesBack) {
  Rig r;
  {
    LeakNode n(r.p, r.gpio);
    n.tick(0);
    EXPECT_TRUE(r.gpio.line("gpiochip0", 27).requested);
  }
  EXPECT_FALSE(r.gpio.line("gpiochip0", 27).requested);
  EXPECT_FALSE(r.gpio.line("gpiochip0", 22).requested);
}

TEST(LeakConfig, StrictLoader) {
  const auto p = load_leak_file(TILLER_SOURCE_DIR "/config/sensors/leak_gpio.yaml");
  ASSERT_EQ(p.probes.size(), 1u);
  EXPECT_EQ(p.probes[0].line, 27u);
  EXPECT_TRUE(p.probes[0].active_high);
  auto error = [](const std::string& text) {
    try {
      load_leak_params(config::Value::parse(text, "leak.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(error("rate_hz: 10\n").find("probes: missing required key"), std::string::npos);
  EXPECT_NE(error("probes:\n  - {name: a, line: 3}\n").find("leak.yaml:2: probes[0].active"),
            std::string::npos)
      << error("probes:\n  - {name: a, line: 3}\n");
  EXPECT_NE(error("probes:\n  - {name: a, line: 3, active: wet}\n").find("high"),
            std::string::npos);
  const std::string dup =
      error("probes:\n  - {name: a, line: 3, active: high}\n  - {name: b, line: 3, active: low}\n");
  EXPECT_NE(dup.find("probes[1].line"), std::string::npos) << dup;
  EXPECT_NE(dup.find("a has it"), std::string::npos) << dup;
  EXPECT_NE(error("probes:\n  - {name: a, line: 3, active: high, bias: up}\n").find("bias"),
            std::string::npos);
  EXPECT_NE(error("probes: []\n").find("1 to 32 probes"), std::string::npos);
}

}  // namespace
}  // namespace tiller::sensors
