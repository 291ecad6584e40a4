// Allocation speed: 4, 6 and 8 thrusters, unsaturated and saturated, every strategy, plus the
// manual (open-loop) mapping. Counts heap allocations inside the timed loop by replacing the
// global operator new in this binary: the "allocs_per_call" counter must read 0.
//   build-*/bench/allocation_bench
#include <benchmark/benchmark.h>

#include <string>

#include "alloc_count.hpp"
#include "allocation/allocator.hpp"

namespace tiller {
namespace {

Vehicle file(const std::string& name) {
  return load_vehicle_file(std::string(TILLER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml");
}

// BlueROV2 Heavy-like: seed 001's vectored four plus four vertical thrusters (8, 6-DOF).
Vehicle heavy8() {
  Vehicle v = file("seed001_rov6");
  v.thrusters.erase(v.thrusters.begin() + 3);  // B
  v.thrusters.erase(v.thrusters.begin());      // F
  const double xs[4] = {0.12, 0.12, -0.12, -0.12}, ys[4] = {-0.22, 0.22, -0.22, 0.22};
  for (int k = 0; k < 4; ++k) {
    Thruster t = v.thrusters[0];
    // Not "V" + std::to_string(k): GCC 12 at -O3 inlines that operator+ and raises a false
    // -Werror=restrict inside std::string (GCC bug 105329 / 105651).
    t.name = std::to_string(k);
    t.name.insert(0, 1, 'V');
    t.position = {xs[k], ys[k], 0.0};
    t.direction = {0, 0, -1};
    t.group = "vertical";
    v.thrusters.push_back(t);
  }
  return v;
}

Vehicle pick(int n) {
  return n == 4 ? file("seed000_rov4") : n == 6 ? file("seed001_rov6") : heavy8();
}

void run(benchmark::State& state, Strategy s, bool manual) {
  const int n = static_cast<int>(state.range(0));
  const bool saturated = state.range(1) != 0;
  Vehicle v = pick(n);
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

#define TILLER_ARGS ArgNames({"thrusters", "saturated"})->ArgsProduct({{4, 6, 8}, {0, 1}})
BENCHMARK(BM_DirectionPreserving)->TILLER_ARGS;
BENCHMARK(BM_Prioritised)->TILLER_ARGS;
BENCHMARK(BM_Clip)->TILLER_ARGS;
BENCHMARK(BM_Manual)->TILLER_ARGS;

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
