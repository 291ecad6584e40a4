// Cost of one 10 ms ESC bus cycle for 4 and 8 ESCs: the node's five 2 ms ticks, a changed
// thruster command delivered mid-cycle and written at once (one write per ESC), and the tick on
// the cycle's grid (safety logic, one write per ESC on the fake bus with device models, one
// telemetry read), each write with its output message encoded; and the heap allocations per
// cycle (must be 0). bus_transactions_per_cycle is 2n + 1 for tgy.
#include <benchmark/benchmark.h>

#include "alloc_count.hpp"
#include "esc_setups.hpp"

namespace {

void run(benchmark::State& state, const char* backend) {
  tiller::test::Steady s(backend, static_cast<int>(state.range(0)));
  for (int k = 0; k < 300; ++k) s.cycle();
  const long before = tiller::test::allocations();
  const auto tx0 = s.bus.transactions();
  for (auto _ : state) {
    s.cycle();
    benchmark::ClobberMemory();
  }
  const double allocs = static_cast<double>(tiller::test::allocations() - before);
  state.counters["allocs_per_cycle"] = allocs / static_cast<double>(state.iterations());
  state.counters["bus_transactions_per_cycle"] =
      static_cast<double>(s.bus.transactions() - tx0) / static_cast<double>(state.iterations());
  if (allocs > 0) state.SkipWithError("the ESC cycle allocated");
}

void BM_EscCycle_Tgy(benchmark::State& state) {
  run(state, "i2c_tgy");
}
void BM_EscCycle_Pca9685(benchmark::State& state) {
  run(state, "pca9685");
}
void BM_EscCycle_Sim(benchmark::State& state) {
  run(state, "sim");
}

BENCHMARK(BM_EscCycle_Tgy)->Arg(4)->Arg(8);
BENCHMARK(BM_EscCycle_Pca9685)->Arg(4)->Arg(8);
BENCHMARK(BM_EscCycle_Sim)->Arg(4)->Arg(8);

}  // namespace

BENCHMARK_MAIN();
