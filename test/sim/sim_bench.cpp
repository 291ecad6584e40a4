// Simulator benchmarks (Google Benchmark):
//   BM_Step3Dof / BM_Step6Dof   one RK4 step of the Otter (surface) and the seed-001 ROV
//                               (underwater) models: steps per second.
//   BM_SimNodeTick              one SimNode tick (step + publishing at 20 Hz) fed by ESC output.
//   BM_ClosedLoopLockstep       SimNode + MixerNode + EscNode (sim backend) in LockstepExecutor,
//                               60 s of simulated time per iteration with a manual demand at
//                               10 Hz; reports x_real_time = simulated seconds / wall seconds
//                               (and x_real_time_cpu, per CPU second of this process).
// Run: build/bench/sim_bench (add --benchmark_filter=... to pick one).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <string>

#include <tiller/arm_request_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "esc/esc_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/sim_node.hpp"

namespace tiller {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

SimVehicle vehicle(const char* name) {
  return load_sim_vehicle_file(kSrc + "/config/vehicles/" + name + ".yaml");
}

void step_bench(benchmark::State& state, const char* name) {
  const SimVehicle v = vehicle(name);
  std::vector<sim::ThrusterGeometry> g;
  for (const auto& t : v.vehicle.thrusters) g.push_back({t.position, t.direction});
  sim::VesselModel m(v.dynamics, g);
  m.reset(sim::Vector6::Zero(), sim::Vector6::Zero());
  for (int i = 0; i < m.n_thrusters(); ++i) m.set_thrust_target(i, 10.0 + 3.0 * i);
  sim::Environment env;
  env.current_ned = sim::Vector3(0.2, 0.1, 0.0);
  for (auto _ : state) {
    m.step(0.01, env);
    benchmark::DoNotOptimize(m.nu().data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_Step3Dof(benchmark::State& state) {
  step_bench(state, "otter");
}
BENCHMARK(BM_Step3Dof);

void BM_Step6Dof(benchmark::State& state) {
  step_bench(state, "seed001_rov6");
}
BENCHMARK(BM_Step6Dof);

class NullBus : public Bus {
 public:
  void publish(std::string_view, const std::uint8_t*, int) override {}
};

void BM_SimNodeTick(benchmark::State& state) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/seed001_rov6.yaml";
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  NullBus bus;
  node.attach(&bus);
  esc_output_t m{};
  m.armed = true;
  m.unit = esc_output_t::UNIT_PULSE_US;
  m.n_channels = node.vehicle().size();
  for (const auto& t : node.vehicle().thrusters) {
    m.names.push_back(t.name);
    m.channel.push_back(0);
    m.value.push_back(1600);
    m.normalized.push_back(0.25);
  }
  TimeUs now = 0;
  for (auto _ : state) {
    node.on_esc_output(m, now);
    node.tick(now);
    now += p.step_us;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SimNodeTick);

void BM_ClosedLoopLockstep(benchmark::State& state) {
  const TimeUs run = 60 * kUsPerSecond;
  double wall = 0, cpu = 0, simulated = 0;
  for (auto _ : state) {
    state.PauseTiming();
    MixerNode mixer(kSrc + "/config/mixer/seed001_rov6.yaml");
    EscNode esc(kSrc + "/config/esc/seed001_sim.yaml");
    SimParams p;
    p.vehicle_file = kSrc + "/config/vehicles/seed001_rov6.yaml";
    SimNode sim(p, load_sim_vehicle_file(p.vehicle_file));
    LockstepExecutor ex(0);
    ex.add(sim);
    ex.add(mixer);
    ex.add(esc);
    arm_request_t arm{};
    arm.arm = true;
    arm.source = "bench";
    ex.inject(channels::kArmRequest, arm, 100'000);
    for (TimeUs t = 200'000; t <= run; t += 100'000) {
      manual_demand_t d{};
      d.utime = t;
      d.valid = true;
      d.demand[0] = 0.5 + 0.5 * std::sin(1e-6 * static_cast<double>(t));
      d.demand[5] = 0.3;
      ex.inject(channels::kManualDemand, d, t);
    }
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    ex.run_until(run);
    const std::clock_t c1 = std::clock();
    const auto t1 = std::chrono::steady_clock::now();
    wall += std::chrono::duration<double>(t1 - t0).count();
    cpu += static_cast<double>(c1 - c0) / CLOCKS_PER_SEC;
    simulated += to_seconds(run);
    benchmark::DoNotOptimize(sim.model().nu().data());
  }
  // Wall-clock and CPU-time multiples (they differ when other jobs share the cores).
  state.counters["x_real_time"] = simulated / wall;
  state.counters["x_real_time_cpu"] = simulated / cpu;
}
BENCHMARK(BM_ClosedLoopLockstep)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
