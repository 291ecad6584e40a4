// Allocation speed: 4, 6 and 8 thrusters (8 in two groups and in one), unsaturated and saturated,
// every strategy, plus the manual (open-loop) mapping, and the one-group 8-thruster saturated
// worst case against the unsaturated pseudo-inverse in the same run (BM_WorstOneGroup8_*). Counts
// heap allocations inside the timed loop by replacing the global operator new in this binary: the
// "allocs_per_call" counter must read 0.
//   build-*/bench/allocation_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <string>

#include "alloc_count.hpp"
#include "allocation/allocator.hpp"
#include "test_util.hpp"

namespace tiller {
namespace {

Vehicle file(const std::string& name) {
  return load_vehicle_file(std::string(TILLER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml");
}

// 4: seed000_rov4, 6: seed001_rov6, 8: the BlueROV2-Heavy-like test::rov8 in two groups
// (horizontal, vertical) or, one_group, all eight in one group (six axes, two spare directions).
Vehicle pick(int n, bool one_group) {
  return n == 4 ? file("seed000_rov4") : n == 6 ? file("seed001_rov6") : test::rov8(one_group);
}

void run(benchmark::State& state, Strategy s, bool manual) {
  const int n = static_cast<int>(state.range(0));
  const bool saturated = state.range(1) != 0;
  Vehicle v = pick(n, state.range(2) != 0);
  v.allocation.strategy = s;
  if (s == Strategy::kPrioritised) v.allocation.priority = {{5}, {0}, {1}, {2}, {4}, {3}};
  const Allocator a(v);
  Wrench w = Wrench::Zero();
  const double size = saturated ? 3.0 : 0.15;
  const double mix[6] = {0.8, -0.5, 0.6, 0.3, -0.4, 0.7};
  for (int ax = 0; ax < 6; ++ax)
    if (!a.unactuated()[static_cast<std::size_t>(ax)])
      w(ax) = manual ? mix[ax] * (saturated ? 1.0 : 0.2) : size * mix[ax] * a.axis_max(ax, 1);
  AllocationResult r;
  manual ? a.allocate_manual(w, r) : a.allocate(w, r);
  if ((r.scale < 1.0) != saturated && !manual) state.SkipWithError("saturation not as intended");
  const long before = test::allocations();
  for (auto _ : state) {
    benchmark::DoNotOptimize(w);
    if (manual)
      a.allocate_manual(w, r);
    else
      a.allocate(w, r);
    benchmark::DoNotOptimize(r);
  }
  state.counters["allocs_per_call"] =
      static_cast<double>(test::allocations() - before) / static_cast<double>(state.iterations());
  state.counters["scale"] = r.scale;
}

void BM_DirectionPreserving(benchmark::State& s) {
  run(s, Strategy::kDirectionPreserving, false);
}
void BM_Prioritised(benchmark::State& s) {
  run(s, Strategy::kPrioritised, false);
}
void BM_Clip(benchmark::State& s) {
  run(s, Strategy::kClip, false);
}
void BM_Manual(benchmark::State& s) {
  run(s, Strategy::kDirectionPreserving, true);
}

#define TILLER_ARGS                                 \
  ArgNames({"thrusters", "saturated", "one_group"}) \
      ->Args({4, 0, 0})                             \
      ->Args({4, 1, 0})                             \
      ->Args({6, 0, 0})                             \
      ->Args({6, 1, 0})                             \
      ->Args({8, 0, 0})                             \
      ->Args({8, 1, 0})                             \
      ->Args({8, 0, 1})                             \
      ->Args({8, 1, 1})
BENCHMARK(BM_DirectionPreserving)->TILLER_ARGS;
BENCHMARK(BM_Prioritised)->TILLER_ARGS;
BENCHMARK(BM_Clip)->TILLER_ARGS;
BENCHMARK(BM_Manual)->TILLER_ARGS;

// ns per call of `calls` calls of a.allocate(w), timed with the steady clock.
double time_calls(const Allocator& a, const Wrench& w, int calls, AllocationResult& r) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < calls; ++k) {
    benchmark::DoNotOptimize(w);
    a.allocate(w, r);
    benchmark::DoNotOptimize(r);
  }
  const auto t1 = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / calls;
}

// The saturated worst case of the one-group 8-thruster ROV: among 400 seeded saturated demands
// (dense and sparse, 1.2 to 5 times what the vehicle can do), the slowest (fastest of 5 rounds
// of 32 calls each, so that a preemption does not pick it); then, in the same run, that demand
// and the unsaturated pseudo-inverse (0.15 of the largest per axis), 200 calls each per
// iteration. Counters: worst_ns and pinv_ns per call, ratio = worst / pinv (target: <= 5, or
// worst <= 1000 ns), allocs_per_call (0).
void worst_one_group(benchmark::State& state, Strategy s) {
  Vehicle v = test::rov8(true);
  v.allocation.strategy = s;
  if (s == Strategy::kPrioritised) v.allocation.priority = {{5}, {0}, {1}, {2}, {4}, {3}};
  const Allocator a(v);
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> size(1.2, 5.0);
  std::bernoulli_distribution keep(0.5);
  AllocationResult r;
  Wrench worst_w = Wrench::Zero();
  double worst = 0;
  for (int k = 0; k < 400; ++k) {
    Wrench w = test::random_wrench(a, rng, size(rng));
    if (k % 2)
      for (int ax = 0; ax < 6; ++ax)
        if (!keep(rng)) w(ax) = 0;
    a.allocate(w, r);
    if (!(r.scale < 1.0)) continue;
    double best = 1e300;
    for (int round = 0; round < 5; ++round) best = std::min(best, time_calls(a, w, 32, r));
    if (best > worst) {
      worst = best;
      worst_w = w;
    }
  }
  Wrench easy = Wrench::Zero();
  const double mix[6] = {0.8, -0.5, 0.6, 0.3, -0.4, 0.7};
  for (int ax = 0; ax < 6; ++ax) easy(ax) = 0.15 * mix[ax] * a.axis_max(ax, 1);
  a.allocate(easy, r);
  for (int i = 0; i < r.n; ++i)
    if (r.saturated[static_cast<std::size_t>(i)] || r.scale < 1.0)
      state.SkipWithError("the unsaturated case saturates");
  double sat_ns = 0, pinv_ns = 0;
  long rounds = 0;
  const long before = test::allocations();
  for (auto _ : state) {
    sat_ns += time_calls(a, worst_w, 200, r);
    pinv_ns += time_calls(a, easy, 200, r);
    ++rounds;
  }
  const long news = test::allocations() - before;
  state.counters["worst_ns"] = sat_ns / static_cast<double>(rounds);
  state.counters["pinv_ns"] = pinv_ns / static_cast<double>(rounds);
  state.counters["ratio"] = sat_ns / pinv_ns;
  state.counters["allocs_per_call"] =
      static_cast<double>(news) / (400.0 * static_cast<double>(rounds));
}

void BM_WorstOneGroup8_DirectionPreserving(benchmark::State& s) {
  worst_one_group(s, Strategy::kDirectionPreserving);
}
void BM_WorstOneGroup8_Prioritised(benchmark::State& s) {
  worst_one_group(s, Strategy::kPrioritised);
}
BENCHMARK(BM_WorstOneGroup8_DirectionPreserving);
BENCHMARK(BM_WorstOneGroup8_Prioritised);

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
