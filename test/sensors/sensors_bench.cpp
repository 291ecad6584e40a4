// Per-sample cost of the sensor drivers, with heap allocations counted (must be 0):
//   BM_Ms5837Compensate: one D1/D2 pair -> temperature and pressure (first + second order);
//   BM_PressureNodeSample: two node ticks on the fake bus (ADC read, next conversion start,
//     compensation, depth, checks, pressure_t encode) = one published sample;
//   BM_GnssReport: one gpsd TPV report (gps_data_t as libgps fills it) -> checked, encoded fix.
#include <benchmark/benchmark.h>
#include <gps.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "alloc_count.hpp"
#include "i2c/fake_bus.hpp"
#include "runtime/node.hpp"
#include "sensors/fake/ms5837_model.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/ms5837.hpp"
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

}  // namespace

BENCHMARK_MAIN();
