// Per-sample cost of the Navigator's drivers through their fake transports, and of one AHRS
// step, with heap allocations counted (must be 0). Budget (issue 33): each read-and-convert
// under 50 us.
//   BM_Icm20602ReadConvert: one 15-byte SPI burst (INT_STATUS + data) -> rad/s, m/s^2, degC;
//   BM_Ak09915ReadConvert: one 9-byte I2C read (ST1..ST2) -> uT;
//   BM_Mmc5983ReadConvert: one 9-byte I2C read (Xout0..Status) -> uT;
//   BM_Bmp280ReadCompensate: one 6-byte burst -> integer and double compensation;
//   BM_Ads1115ReadConvert: one conversion register read and the next single-shot start -> V;
//   BM_MahonyUpdate: one filter step with gyro, accelerometer and magnetometer.
#include <benchmark/benchmark.h>

#include "ahrs/mahony.hpp"
#include "alloc_count.hpp"
#include "i2c/fake_bus.hpp"
#include "sensors/ads1115.hpp"
#include "sensors/ak09915.hpp"
#include "sensors/bmp280.hpp"
#include "sensors/fake/navigator_models.hpp"
#include "sensors/icm20602.hpp"
#include "sensors/mmc5983.hpp"
#include "spi/fake_spi.hpp"

namespace {
using namespace tiller;
using namespace tiller::sensors;

void report_allocs(benchmark::State& state, long before) {
  const double allocs = static_cast<double>(test::allocations() - before);
  state.counters["allocs_per_sample"] = allocs / static_cast<double>(state.iterations());
  if (allocs > 0) state.SkipWithError("a sample allocated");
}

void BM_Icm20602ReadConvert(benchmark::State& state) {
  spi::FakeSpi bus("/dev/spidev1.0");
  fake::Icm20602Model chip;
  bus.attach(&chip);
  icm20602::Device dev(bus, {});
  if (dev.start() != 0) state.SkipWithError("start failed");
  icm20602::Burst b{};
  TimeUs t = bus.now();
  const long before = test::allocations();
  for (auto _ : state) {
    bus.set_time(t += 10'000);
    dev.read(b);
    const auto s = icm20602::convert(b, dev.config());
    benchmark::DoNotOptimize(s);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Icm20602ReadConvert);

void BM_Ak09915ReadConvert(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ak09915Model chip;
  bus.attach(ak09915::kAddress, &chip);
  ak09915::Device dev(bus, ak09915::kAddress, 100);
  if (dev.start() != 0) state.SkipWithError("start failed");
  ak09915::Burst b{};
  TimeUs t = bus.now();
  const long before = test::allocations();
  for (auto _ : state) {
    bus.set_time(t += 10'000);
    dev.read(b);
    const auto s = ak09915::convert(b);
    benchmark::DoNotOptimize(s);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Ak09915ReadConvert);

void BM_Mmc5983ReadConvert(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Mmc5983Model chip;
  bus.attach(mmc5983::kAddress, &chip);
  mmc5983::Device dev(bus, mmc5983::kAddress, 100);
  if (dev.start() != 0) state.SkipWithError("start failed");
  mmc5983::Burst b{};
  TimeUs t = bus.now();
  const long before = test::allocations();
  for (auto _ : state) {
    bus.set_time(t += 10'000);
    dev.read(b);
    const auto s = mmc5983::convert(b);
    benchmark::DoNotOptimize(s);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Mmc5983ReadConvert);

void BM_Bmp280ReadCompensate(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Bmp280Model chip;
  bus.attach(bmp280::kAddress, &chip);
  bmp280::Device dev(bus, bmp280::kAddress, {});
  if (dev.start() != 0) state.SkipWithError("start failed");
  bmp280::Result r;
  const long before = test::allocations();
  for (auto _ : state) {
    dev.read(r);
    benchmark::DoNotOptimize(r);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Bmp280ReadCompensate);

void BM_Ads1115ReadConvert(benchmark::State& state) {
  i2c::FakeBus bus("/dev/i2c-1");
  fake::Ads1115Model chip;
  chip.input_v[2] = 1.5;
  bus.attach(ads1115::kAddress, &chip);
  ads1115::Device dev(bus, ads1115::kAddress, 1, 7);
  if (dev.probe() != 0) state.SkipWithError("probe failed");
  TimeUs t = 0;
  dev.start(2);
  const long before = test::allocations();
  for (auto _ : state) {
    bus.set_time(t += ads1115::conversion_us(7));
    std::uint16_t raw = 0;
    dev.read(raw);
    dev.start(2);
    benchmark::DoNotOptimize(ads1115::volts(raw, 1));
  }
  report_allocs(state, before);
}
BENCHMARK(BM_Ads1115ReadConvert);

void BM_MahonyUpdate(benchmark::State& state) {
  ahrs::Mahony f;
  const ahrs::Vec3 g{0.01, -0.02, 0.2}, a{0.1, -0.2, -9.8}, m{20, 1, 45};
  f.align(a, m);
  const long before = test::allocations();
  for (auto _ : state) {
    f.update(g, a, &m, 0.01);
    benchmark::DoNotOptimize(f.q());
  }
  report_allocs(state, before);
}
BENCHMARK(BM_MahonyUpdate);

}  // namespace

BENCHMARK_MAIN();
