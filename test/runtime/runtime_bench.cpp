// Runtime costs: one message through the lockstep executor (encode, queue, decode, handle),
// a full closed loop of two nodes in multiples of real time, and encode/decode of odometry.
#include <benchmark/benchmark.h>

#include "echo_node.hpp"
#include "runtime/event.hpp"
#include "runtime/lockstep.hpp"

namespace tiller {
namespace {

void BM_LockstepClosedLoop(benchmark::State& state) {
  test::ToyController c;
  test::ToyPlant p;
  LockstepExecutor ex(0);
  ex.add(p);
  ex.add(c);
  TimeUs t = 0;
  std::int64_t sim_us = 0;
  for (auto _ : state) {
    t += kUsPerSecond;
    ex.run_until(t);
    sim_us += kUsPerSecond;
  }
  state.counters["messages"] = benchmark::Counter(static_cast<double>(c.received() + p.received()),
                                                  benchmark::Counter::kIsRate);
  state.counters["x_realtime"] =
      benchmark::Counter(to_seconds(sim_us), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_LockstepClosedLoop)->Unit(benchmark::kMicrosecond);

void BM_OdometryEncodeDecode(benchmark::State& state) {
  odometry_t o{};
  o.position[0] = 1.0;
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(o.getEncodedSize()));
  odometry_t out{};
  for (auto _ : state) {
    o.encode(buf.data(), 0, static_cast<int>(buf.size()));
    out.decode(buf.data(), 0, static_cast<int>(buf.size()));
    benchmark::DoNotOptimize(out.position[0]);
  }
}
BENCHMARK(BM_OdometryEncodeDecode);

void BM_NodeDeliver(benchmark::State& state) {
  test::ToyController c;
  odometry_t o{};
  o.position[0] = 0.5;
  const Event e = encode("TILLER_ODOMETRY", 0, o);
  const std::string ch = "TILLER_ODOMETRY";
  TimeUs t = 0;
  for (auto _ : state) {
    c.deliver(ch, e.data.data(), static_cast<int>(e.data.size()), ++t);
  }
  benchmark::DoNotOptimize(c.x_);
}
BENCHMARK(BM_NodeDeliver);

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
