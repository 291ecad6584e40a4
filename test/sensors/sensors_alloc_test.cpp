// The sensor drivers' steady state allocates nothing: 30 s of ticks of each node on its fake
// (bus transactions, conversion, checks, the published messages and the 1 Hz heartbeats),
// after a warm-up, counted with the replaced operator new (test/common/alloc_count.hpp).
#include <gtest/gtest.h>

#include "alloc_count.hpp"
#include "i2c/fake_bus.hpp"
#include "runtime/node.hpp"
#include "sensors/fake/bno055_model.hpp"
#include "sensors/fake/ina226_model.hpp"
#include "sensors/fake/ms5837_model.hpp"
#include "sensors/gpio.hpp"
#include "sensors/imu_node.hpp"
#include "sensors/leak_node.hpp"
#include "sensors/power_node.hpp"
#include "sensors/pressure_node.hpp"

namespace tiller::sensors {
namespace {

struct NullBus : Bus {
  std::int64_t messages = 0;
  void publish(std::string_view, const std::uint8_t*, int) override { ++messages; }
};

// Ticks `node` for 5 s, then counts the allocations of the next 30 s.
long steady_allocations(Node& node, auto&& each_tick) {
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (; t < 5 * kUsPerSecond; t += node.tick_period()) {
    each_tick(t);
    node.tick(t);
  }
  const long before = test::allocations();
  for (; t < 35 * kUsPerSecond; t += node.tick_period()) {
    each_tick(t);
    node.tick(t);
  }
  const long n = test::allocations() - before;
  EXPECT_GT(out.messages, 30);
  return n;
}

TEST(SensorsAllocation, ImuNode) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Bno055Model dev;
  dev.set_quaternion(11585, 0, 0, -11585);
  dev.set_vector(0x08, 0, 0, 981);
  bus.attach(0x28, &dev);
  ImuNode node(ImuParams{}, bus);
  EXPECT_EQ(steady_allocations(node, [](TimeUs) {}), 0);
  EXPECT_GT(node.counter_value("headings"), 1500);
}

TEST(SensorsAllocation, ImuNodeCalibrating) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Bno055Model dev;
  dev.calib_stat = 0x3F;  // DEGRADED, "calibrating": the status is built once
  dev.set_quaternion(16384, 0, 0, 0);
  bus.attach(0x28, &dev);
  ImuNode node(ImuParams{}, bus);
  EXPECT_EQ(steady_allocations(node, [](TimeUs) {}), 0);
}

TEST(SensorsAllocation, PowerNode) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ina226Model dev;
  dev.shunt = 0x1F40;
  dev.bus = 0x2570;
  bus.attach(0x40, &dev);
  PowerParams p;
  p.config = ina226::config_word(2, 4, 4);
  PowerNode node(p, bus);
  EXPECT_EQ(steady_allocations(node, [](TimeUs) {}), 0);
  EXPECT_GT(node.counter_value("samples"), 300);
}

TEST(SensorsAllocation, PressureNode) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ms5837Model dev({0x2000, 34982, 36352, 20328, 22354, 26646, 26146});
  dev.d1 = 4958179;
  dev.d2 = 6815414;
  bus.attach(0x76, &dev);
  PressureNode node(PressureParams{}, bus);
  EXPECT_EQ(steady_allocations(node, [](TimeUs) {}), 0);
}

TEST(SensorsAllocation, LeakNodeWithAFlickeringProbe) {
  FakeGpio gpio;
  LeakParams p;
  for (unsigned i = 0; i < 4; ++i)
    p.probes.push_back({"probe" + std::to_string(i), "gpiochip0", i, i % 2 == 0, Bias::as_is});
  LeakNode node(p, gpio);
  // Probe 2 drips every 0.5 s from the warm-up on: wet held, one status.
  EXPECT_EQ(steady_allocations(
                node, [&](TimeUs t) { gpio.line("gpiochip0", 2).level = (t / 500'000) % 2 == 0; }),
            0);
  EXPECT_TRUE(node.last().wet[2]);
}

}  // namespace
}  // namespace tiller::sensors
