// Per-sample cost of the sensor drivers, with heap allocations counted (must be 0):
//   BM_Ms5837Compensate: one D1/D2 pair -> temperature and pressure (first + second order);
//   BM_PressureNodeSample: two node ticks on the fake bus (ADC read, next conversion start,
//     compensation, depth, checks, pressure_t encode) = one published sample;
//   BM_GnssReport: one gpsd TPV report (gps_data_t as libgps fills it) -> checked, encoded fix;
//   BM_Bno055Convert: one 54-byte BNO055 burst -> decoded registers -> imu_t fields and yaw;
//   BM_ImuNodeSample: one tiller-imu tick on the fake bus (burst read, decode, convert, checks,
//     imu_t and heading_t encoded);
//   BM_PowerNodeSample: one tiller-power tick on the fake bus (four register reads, scaling,
//     charge and energy integration, checks, power_t encoded);
//   BM_LeakNodeTick: one tiller-leak tick with 4 probes on fake GPIO lines (reads, dry filter,
//     checks, leak_t encoded).
#include <benchmark/benchmark.h>
#include <gps.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "alloc_count.hpp"
#include "i2c/fake_bus.hpp"
#include "runtime/node.hpp"
#include "sensors/bno055.hpp"
#include "sensors/fake/bno055_model.hpp"
#include "sensors/fake/ina226_model.hpp"
#include "sensors/fake/ms5837_model.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/gpio.hpp"
#include "sensors/imu_node.hpp"
#include "sensors/leak_node.hpp"
#include "sensors/ms5837.hpp"
#include "sensors/power_node.hpp"
#include "sensors/pressure_node.hpp"

namespace {
using namespace tiller;
using namespace tiller::sensors;

constexpr ms5837::Prom kProm = {0x2000, 34982, 36352, 20328, 22354, 26646, 26146};

void report_allocs(benchmark::State& state, long before) {
  const double allocs = static_cast<double>(test::allocations() - before);
  state.counters["allocs_per_sample"] = allocs / static_cast<double>(state.iterations());
  if (allocs > 0) state.SkipWithError("a sample allocated");
}

void BM_Ms5837Compensate(benchmark::State& state) {
  std::uint32_t d1 = 4958179;
  const long before = test::allocations();
  for (auto _ : state) {
    const auto r = ms5837::compensate(ms5837::Model::ba30, kProm, d1, 6815414);
    benchmark::DoNotOptimize(r);
    d1 ^= 1;
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Ms5837Compensate);

struct NullBus : Bus {
  void publish(std::string_view, const std::uint8_t*, int) override {}
};

void BM_PressureNodeSample(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ms5837Model dev(kProm);
  dev.d1 = 4958179;
  dev.d2 = 6815414;
  bus.attach(0x76, &dev);
  PressureParams p;
  PressureNode node(p, bus);
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (int i = 0; i < 100; ++i, t += node.tick_period()) node.tick(t);  // set up, warm up
  const long before = test::allocations();
  for (auto _ : state) {
    node.tick(t);
    t += node.tick_period();
    node.tick(t);
    t += node.tick_period();
  }
  report_allocs(state, before);
  if (node.counter_value("samples") < state.iterations()) state.SkipWithError("samples missing");
}
BENCHMARK(BM_PressureNodeSample);

void BM_GnssReport(benchmark::State& state) {
  auto d = std::make_unique<gps_data_t>();
  std::memset(d.get(), 0, sizeof(gps_data_t));
  d->set = MODE_SET | TIME_SET | LATLON_SET;
  d->fix.mode = MODE_3D;
  d->fix.status = STATUS_FIX;
  d->fix.time.tv_sec = 1'796'126'400;
  d->fix.latitude = 59.437;
  d->fix.longitude = 10.6612;
  d->fix.altHAE = 52.1;
  d->fix.altMSL = 12.3;
  d->fix.epx = d->fix.epy = 17.1;
  d->fix.epv = 29.9;
  d->fix.speed = 1.543;
  d->fix.track = 45.0;
  std::strcpy(d->dev.path, "/dev/pts/1");
  GnssNode node(GnssParams{});
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (int i = 0; i < 10; ++i) node.on_gps(*d, t += 1000);
  const long before = test::allocations();
  for (auto _ : state) {
    t += 1000;
    d->fix.latitude += 1e-9;
    node.on_gps(*d, t);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_GnssReport);

void BM_Bno055Convert(benchmark::State& state) {
  bno055::Burst b{};
  b[0x20 - 0x08] = 0x00;  // quaternion w = 16384 (1.0)
  b[0x21 - 0x08] = 0x40;
  b[0x0C - 0x08] = 0xD5;  // ACC z = 981 (9.81 m/s^2)
  b[0x0D - 0x08] = 0x03;
  b[bno055::kRegSysStatus - 0x08] = bno055::kSysStatusFusionRunning;
  imu_t m{};
  const bno055::Mount mount;
  const long before = test::allocations();
  for (auto _ : state) {
    const bno055::Raw raw = bno055::decode(b);
    benchmark::DoNotOptimize(bno055::convert(raw, mount, 0, m));
    b[0x14 - 0x08] ^= 1;  // the gyro changes
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Bno055Convert);

void BM_ImuNodeSample(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Bno055Model dev;
  dev.set_quaternion(11585, 0, 0, -11585);
  dev.set_vector(0x08, 0, 0, 981);
  bus.attach(0x28, &dev);
  ImuParams p;
  ImuNode node(p, bus);
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (int i = 0; i < 100; ++i, t += node.tick_period()) node.tick(t);  // set up, warm up
  const long before = test::allocations();
  const auto samples = node.counter_value("samples");
  for (auto _ : state) {
    node.tick(t);
    t += node.tick_period();
  }
  report_allocs(state, before);
  if (node.counter_value("samples") - samples < state.iterations())
    state.SkipWithError("samples missing");
}
BENCHMARK(BM_ImuNodeSample);

void BM_PowerNodeSample(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ina226Model dev;
  dev.shunt = 0x1F40;  // the data sheet's example: 20 mV, 11.98 V
  dev.bus = 0x2570;
  bus.attach(0x40, &dev);
  PowerParams p;
  p.config = ina226::config_word(2, 4, 4);
  PowerNode node(p, bus);
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (int i = 0; i < 100; ++i, t += node.tick_period()) node.tick(t);
  const long before = test::allocations();
  const auto samples = node.counter_value("samples");
  for (auto _ : state) {
    node.tick(t);
    t += node.tick_period();
  }
  report_allocs(state, before);
  if (node.counter_value("samples") - samples < state.iterations())
    state.SkipWithError("samples missing");
}
BENCHMARK(BM_PowerNodeSample);

void BM_LeakNodeTick(benchmark::State& state) {
  FakeGpio gpio;
  LeakParams p;
  for (unsigned i = 0; i < 4; ++i)
    p.probes.push_back({"probe" + std::to_string(i), "gpiochip0", i, true, Bias::as_is});
  LeakNode node(p, gpio);
  NullBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (int i = 0; i < 100; ++i, t += node.tick_period()) {  // the status says the leak once
    gpio.line("gpiochip0", 2).level ^= 1;
    node.tick(t);
  }
  const long before = test::allocations();
  for (auto _ : state) {
    gpio.line("gpiochip0", 2).level ^= 1;  // a probe that flickers: wet, held wet
    node.tick(t);
    t += node.tick_period();
  }
  report_allocs(state, before);
}
BENCHMARK(BM_LeakNodeTick);

}  // namespace

BENCHMARK_MAIN();
