// Cost of tiller-nav's filter and node, with heap allocations counted (must be 0):
//   BM_EkfPredict: one 20 ms predict (state, Jacobian, F P F^T + Q);
//   BM_EkfUpdate*: one update of each measurement (innovation, S, gate, gain, Joseph form);
//     the filter is restored from a copy every 1024 updates so P stays realistic;
//   *Sway: the same with the sway constraint in use (the current correlated with the rest, so
//     predict carries the cross covariance and updates run on all 12 states, not the first 10);
//   BM_NavNodeTick: one tick of the node (predict to now, validity, odometry_t filled and
//     encoded) after its IMU sample, with a heading and a fix every 10th, and BM_NavNodeGnss /
//     BM_NavNodeImu: one fix (GeographicLib LocalCartesian forward, lag compensation, position and
//     velocity updates) / one IMU sample handled.
#include <benchmark/benchmark.h>

#include <cmath>

#include "alloc_count.hpp"
#include "nav/ekf.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/node.hpp"
#include "synthetic.hpp"

namespace {
using namespace tiller;
using namespace tiller::nav;

void report_allocs(benchmark::State& state, long before) {
  const double allocs = static_cast<double>(tiller::test::allocations() - before);
  state.counters["allocs"] = allocs / static_cast<double>(state.iterations());
  if (allocs > 0) state.SkipWithError("allocated");
}

// A filter as it is in steady state: a few seconds of predicts and updates (and sway updates).
Ekf settled(bool sway = false) {
  Ekf f;
  State x = State::Zero();
  x(kU) = 1.5;
  x(kPsi) = 0.3;
  Covariance p = Covariance::Identity();
  f.reset(x, p);
  Motion m;
  m.r = 0.05;
  for (int i = 0; i < 250; ++i) {
    f.predict(0.02, m);
    if (i % 10 == 0) {
      f.update_position_ne(f.x().segment<2>(kN), Eigen::Matrix2d::Identity() * 4.5, 13.8);
      f.update_heading(f.x()(kPsi), 1e-3, 10.8);
    }
    if (sway) f.update_sway(m, 0.02, 0.5, 10.8);
  }
  return f;
}

void BM_EkfPredict(benchmark::State& state, bool sway) {
  Ekf f = settled(sway);
  const Ekf base = f;
  Motion m;
  m.roll = 0.02;
  m.pitch = -0.01;
  m.r = 0.05;
  int i = 0;
  const long before = tiller::test::allocations();
  for (auto _ : state) {
    f.predict(0.02, m);
    benchmark::DoNotOptimize(f.P().data());
    if ((++i & 1023) == 0) f = base;
  }
  report_allocs(state, before);
}
BENCHMARK_CAPTURE(BM_EkfPredict, , false);
BENCHMARK_CAPTURE(BM_EkfPredict, Sway, true);

template <class Update>
void run_update(benchmark::State& state, Update&& update, bool sway = false) {
  Ekf f = settled(sway);
  const Ekf base = f;
  int i = 0;
  const long before = tiller::test::allocations();
  for (auto _ : state) {
    benchmark::DoNotOptimize(update(f, i));
    if ((++i & 1023) == 0) f = base;
  }
  report_allocs(state, before);
}

void BM_EkfUpdatePosition(benchmark::State& state, bool sway) {
  run_update(
      state,
      [](Ekf& f, int i) {
        const Eigen::Vector2d z(0.3 * (i & 1), -0.2);
        return f
            .update_position_ne(f.x().segment<2>(kN) + z, Eigen::Matrix2d::Identity() * 4.5, 13.8)
            .nis;
      },
      sway);
}
BENCHMARK_CAPTURE(BM_EkfUpdatePosition, , false);
BENCHMARK_CAPTURE(BM_EkfUpdatePosition, Sway, true);

void BM_EkfUpdateSway(benchmark::State& state) {
  Motion m;
  m.r = 0.05;
  run_update(
      state,
      [&m](Ekf& f, int i) { return f.update_sway(m, 0.02 + 0.001 * (i & 1), 0.5, 10.8).nis; },
      true);
}
BENCHMARK(BM_EkfUpdateSway);

void BM_EkfUpdateVelocity(benchmark::State& state) {
  Motion m;
  m.roll = 0.02;
  run_update(state, [&m](Ekf& f, int i) {
    const Eigen::Vector2d z(1.4 + 0.01 * (i & 1), 0.45);
    return f.update_velocity_ne(z, Eigen::Matrix2d::Identity() * 0.01, m, 13.8).nis;
  });
}
BENCHMARK(BM_EkfUpdateVelocity);

void BM_EkfUpdateHeading(benchmark::State& state) {
  run_update(state,
             [](Ekf& f, int i) { return f.update_heading(0.3 + 0.01 * (i & 1), 1e-3, 10.8).nis; });
}
BENCHMARK(BM_EkfUpdateHeading);

void BM_EkfUpdateDepth(benchmark::State& state) {
  run_update(state, [](Ekf& f, int i) { return f.update_depth(0.01 * (i & 1), 2.5e-3, 10.8).nis; });
}
BENCHMARK(BM_EkfUpdateDepth);

void BM_EkfUpdateDvl(benchmark::State& state) {
  run_update(state, [](Ekf& f, int i) {
    const Eigen::Vector3d z(0.2 + 0.001 * (i & 1), -0.05, 0.01);
    return f.update_velocity_body(z, Eigen::Matrix3d::Identity() * 2.5e-5, 16.3).nis;
  });
}
BENCHMARK(BM_EkfUpdateDvl);

struct NullBus : Bus {
  void publish(std::string_view, const std::uint8_t*, int) override {}
};

NavParams usv() {
  return load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/usv.yaml");
}

// A node after 10 s of synthetic input, the vehicle at rest (so nothing changes state later:
// the heartbeat's status, built only on a change, is not rebuilt while timed).
struct Warm {
  Warm() : node(usv()), syn({{1e6, 0.0}}, 1) {
    syn.mutable_truth().u = 0;
    node.attach(&bus);
    for (; t <= 10'000'000; t += 10'000) step();
  }
  void step() {
    syn.advance_to(t);
    if (t % 20'000 == 0) node.tick(t);
    node.on_imu(syn.imu(t), t);
    if (t % 100'000 == 0) node.on_heading(syn.heading(t), t);
    if (t % 200'000 == 0) node.on_gnss(syn.gnss(t), t);
  }
  NullBus bus;
  NavNode node;
  nav::test::Synthetic syn;
  TimeUs t = 0;
};

// One 20 ms tick with the IMU sample before it; every 10th also a heading and a fix (all
// messages made once, restamped).
void BM_NavNodeTick(benchmark::State& state) {
  Warm w;
  imu_t imu = w.syn.imu(w.t);
  heading_t hd = w.syn.heading(w.t);
  gnss_fix_t fix = w.syn.gnss(w.t);
  int i = 0;
  const long before = tiller::test::allocations();
  for (auto _ : state) {
    w.t += 20'000;
    imu.utime = w.t;
    w.node.on_imu(imu, w.t);
    if (++i % 10 == 0) {
      hd.utime = fix.utime = w.t;
      w.node.on_heading(hd, w.t);
      w.node.on_gnss(fix, w.t);
    }
    w.node.tick(w.t);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_NavNodeTick);

void BM_NavNodeGnss(benchmark::State& state) {
  Warm w;
  gnss_fix_t fix = w.syn.gnss(w.t);
  const long before = tiller::test::allocations();
  for (auto _ : state) {
    w.t += 200;  // the same fix, a little later each time (lag compensation included)
    fix.utime = w.t;
    w.node.on_gnss(fix, w.t);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_NavNodeGnss);

void BM_NavNodeImu(benchmark::State& state) {
  Warm w;
  imu_t m = w.syn.imu(w.t);
  const long before = tiller::test::allocations();
  for (auto _ : state) {
    w.t += 10'000;
    m.utime = w.t;
    w.node.on_imu(m, w.t);
  }
  report_allocs(state, before);
}
BENCHMARK(BM_NavNodeImu);

// An ROV on the DVL (config/nav/rov_dvl.yaml) after 10 s: one 20 ms tick with its IMU sample,
// every 5th also a heading, a pressure sample and a DVL report (10 Hz); the once-a-second dead
// reckoning status line is rebuilt inside the timed loop.
void BM_NavNodeRovDvlTick(benchmark::State& state) {
  NullBus bus;
  NavNode node(load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/rov_dvl.yaml"));
  node.attach(&bus);
  nav::test::Synthetic syn({{1e6, 0.0}}, 2);
  syn.mutable_truth().u = 0.2;
  syn.mutable_truth().d = 5.0;
  TimeUs t = 0;
  imu_t imu = syn.imu(0);
  heading_t hd = syn.heading(0);
  pressure_t pr = syn.pressure(0);
  dvl_t dv = syn.dvl(0);
  int i = 0;
  const auto step = [&] {
    t += 20'000;
    imu.utime = t;
    node.on_imu(imu, t);
    if (++i % 5 == 0) {
      hd.utime = pr.utime = dv.utime = t;
      node.on_heading(hd, t);
      node.on_pressure(pr, t);
      node.on_dvl(dv, t);
    }
    node.tick(t);
  };
  while (t < 10'000'000) step();
  const long before = tiller::test::allocations();
  for (auto _ : state) step();
  report_allocs(state, before);
}
BENCHMARK(BM_NavNodeRovDvlTick);

}  // namespace

BENCHMARK_MAIN();
