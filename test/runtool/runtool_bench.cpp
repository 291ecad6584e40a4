// tiller-run's cost (Google Benchmark): one run of config/missions/default.yaml on the Otter with
// its shipped configs, as tiller-run flies it (config loading, the seven nodes in lockstep,
// scoring), without and with the LCM log; counters: simulated seconds per run and multiples of
// real time in CPU time.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "runtool/run.hpp"

namespace tiller::runtool {
namespace {

void BM_RunDefaultMission(benchmark::State& state) {
  RunSpec s;
  s.mission_file = std::string(TILLER_SOURCE_DIR) + "/config/missions/default.yaml";
  if (state.range(0))
    s.log_file = (std::filesystem::temp_directory_path() / "tiller-runtool-bench.lcmlog").string();
  double sim = 0;
  for (auto _ : state) {
    const auto o = run(s);
    sim += o.sim_s;
    benchmark::DoNotOptimize(o.scores.path_scores.cross_track_rms);
  }
  state.SetLabel(state.range(0) ? "default mission, logged" : "default mission");
  state.counters["sim_s"] = sim / static_cast<double>(state.iterations());
  state.counters["x_real_time"] = benchmark::Counter(sim, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RunDefaultMission)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tiller::runtool

BENCHMARK_MAIN();
