// Missions benchmark: runs the shipped missions in lockstep with the seed-faithful follower
// settings (config/guidance/seed.yaml: linear end slow-down, no integral) beside Tiller's
// defaults (config/guidance/<vehicle>.yaml: default.yaml with the vehicle's braking) and a variant
// that differs from the defaults only in the end slow-down (linear), prints a table of scores, then
// measures the closed loop's speed in multiples of real time with Google Benchmark.
#include <benchmark/benchmark.h>

#include <cstdio>

#include "control/station_pid.hpp"
#include "control/velocity_pid.hpp"
#include "guidance/path_follower.hpp"
#include "harness.hpp"
#include "plants.hpp"

namespace tiller::test {
namespace {

struct Variant {
  const char* name;
  const char* guidance;
  bool linear_end;
};
const Variant kVariants[] = {
    {"seed", "config/guidance/seed.yaml", false},
    {"tiller-linear-end", nullptr, true},  // nullptr: the vehicle's config/guidance/<vehicle>.yaml
    {"tiller", nullptr, false},
};
const char* kMissions[] = {"default", "vrx_wayfinding", "station_keeping"};

RunConfig make(const PlantSpec& v, const char* mission, const Variant& var) {
  RunConfig c;
  c.mission_file = std::string("config/missions/") + mission + ".yaml";
  c.guidance_file = var.guidance ? var.guidance : v.guidance_file;
  c.control_file = v.control_file;
  c.make_plant = v.make;
  c.pose_channel = v.pose_channel;
  if (var.linear_end) {
    c.tweak_follower = [](guidance::FollowerNodeParams& p) {
      p.follower.end_slowdown = guidance::EndSlowdown::kLinear;
    };
  }
  return c;
}

void print_table() {
  std::printf("Missions in lockstep, current 0.3 m/s from 30 deg. Lower is better except xRT.\n");
  std::printf("%-16s %-16s %-18s %8s %8s %7s %7s %8s %8s %5s %9s\n", "vehicle", "mission",
              "settings", "xte_rms", "xte_max", "time_s", "final", "vrx_way", "vrx_sk", "miss",
              "xRT");
  for (const auto& v : plants()) {
    for (const char* m : kMissions) {
      for (const auto& var : kVariants) {
        const auto r = run_mission(make(v, m, var));
        std::printf("%-16s %-16s %-18s %8.3f %8.3f %7.1f %7.3f %8.3f %8.3f %5d %9.0f\n",
                    v.name.c_str(), m, var.name, r.path.cross_track_rms, r.path.cross_track_max,
                    r.completed ? r.completed_at : -1.0, r.path.final_position_error,
                    r.path.vrx_wayfinding, r.station_vrx, r.path.waypoints_missed,
                    r.sim_s / std::max(r.wall_s, 1e-9));
      }
    }
  }
  std::fflush(stdout);
}

void BM_Mission(benchmark::State& state) {
  const auto& v = plants()[static_cast<std::size_t>(state.range(0))];
  const auto c = make(v, "vrx_wayfinding", kVariants[2]);
  double sim = 0, wall = 0;
  for (auto _ : state) {
    const auto r = run_mission(c);
    sim += r.sim_s;
    wall += r.wall_s;
  }
  state.SetLabel(v.name + " vrx_wayfinding");
  state.counters["x_real_time"] = sim / wall;
  state.counters["sim_s"] = sim / static_cast<double>(state.iterations());
}

// The hot paths: one follower update on a 6-point course, one step of each PID.
void BM_FollowerUpdate(benchmark::State& state) {
  guidance::PathFollower f;
  std::vector<guidance::Waypoint> pts(6);
  const double xy[6][2] = {{0, 0}, {30, 0}, {30, 20}, {50, 20}, {10, 26}, {10, 40}};
  for (int k = 0; k < 6; ++k) pts[static_cast<std::size_t>(k)].position = {xy[k][0], xy[k][1]};
  f.set_path(pts, {0, 0}, 0, false);
  double n = 0;
  for (auto _ : state) {
    n += 1e-4;
    auto o = f.update({n, 0.3}, 0.01, 0.05);
    benchmark::DoNotOptimize(o);
  }
}
BENCHMARK(BM_FollowerUpdate);

void BM_VelocityPidStep(benchmark::State& state) {
  control::VelocityPidParams p;
  p.surge = {51, 72, 300, 40, 100, 650};
  p.yaw = {400, 0, 600, 200, 200, 1500};
  control::VelocityPid pid(p);
  control::VelocityPidInput in;
  in.u_sp = 1.5;
  in.yaw_mode = control::YawMode::kHeading;
  in.yaw_value = 0.5;
  in.dt = 0.05;
  for (auto _ : state) {
    auto t = pid.step(in);
    benchmark::DoNotOptimize(t);
  }
}
BENCHMARK(BM_VelocityPidStep);

void BM_StationPidStep(benchmark::State& state) {
  control::StationPidParams p;
  p.x = p.y = {150, 20, 350, 150, 500};
  p.yaw = {600, 50, 600, 200, 1200};
  control::StationPid pid(p);
  control::StationPidInput in;
  in.target_n = 1;
  in.target_e = 0.5;
  in.target_heading = 0.3;
  in.dt = 0.05;
  for (auto _ : state) {
    auto t = pid.step(in);
    benchmark::DoNotOptimize(t);
  }
}
BENCHMARK(BM_StationPidStep);

}  // namespace
}  // namespace tiller::test

int main(int argc, char** argv) {
  tiller::test::print_table();
  for (std::size_t k = 0; k < tiller::test::plants().size(); ++k) {
    benchmark::RegisterBenchmark("BM_Mission", tiller::test::BM_Mission)
        ->Arg(static_cast<int>(k))
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
