// Runtime costs: one message through a node (decode, handle), a full closed loop of two nodes
// in the lockstep executor in multiples of real time, the replay executor's throughput over
// the log of such a run, encode/decode of odometry, and (under tools/netns-run only: it opens
// udpm) a round trip through the live executor between two LCM instances (two hops).
#include <benchmark/benchmark.h>
#include <lcm/lcm-cpp.hpp>

#include <atomic>
#include <thread>

#include "echo_node.hpp"
#include "runtime/event.hpp"
#include "runtime/live.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/replay.hpp"

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

// The controller's inputs from 60 s of closed loop, replayed through a fresh controller.
void BM_ReplayThroughput(benchmark::State& state) {
  std::vector<Event> log;
  {
    test::ToyController c;
    test::ToyPlant p;
    LockstepExecutor ex(0);
    ex.add(p);
    ex.add(c);
    ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      if (ch == "TILLER_ODOMETRY") log.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
    });
    ex.run_until(60 * kUsPerSecond);
  }
  std::int64_t messages = 0;
  for (auto _ : state) {
    test::ToyController c;
    ReplayExecutor rep(c);
    rep.run(log);
    messages += c.received();
    benchmark::DoNotOptimize(rep.outputs().size());
  }
  state.counters["messages"] =
      benchmark::Counter(static_cast<double>(messages), benchmark::Counter::kIsRate);
  state.counters["x_realtime"] = benchmark::Counter(60.0 * static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ReplayThroughput)->Unit(benchmark::kMillisecond);

// Answers every odometry at once with a wrench carrying the odometry's position[0].
class Echo : public Node {
 public:
  Echo() : Node("bench-echo", kUsPerSecond) {
    subscribe("TILLER_ODOMETRY", &Echo::on_odometry);
    advertise<wrench_t>("TILLER_WRENCH_VELOCITY");
  }
  void on_odometry(const odometry_t& o, TimeUs now) {
    w_.utime = now;
    w_.tau[0] = o.position[0];
    publish("TILLER_WRENCH_VELOCITY", w_);
  }
  void on_tick(TimeUs) override {}
  wrench_t w_{};
};

struct Client {
  void on_wrench(const lcm::ReceiveBuffer*, const std::string&, const wrench_t* w) {
    last = w->tau[0];
  }
  double last = -1;
};

// One round trip client -> live executor (decode, handler, publish) -> client: two udpm hops.
void BM_LiveRoundTrip(benchmark::State& state) {
  const char* url = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
  lcm::LCM client(url);
  if (!client.good()) {
    state.SkipWithError("udpm unavailable: run under tools/netns-run");
    return;
  }
  Echo echo;
  LiveExecutor ex(url);
  ex.add(echo);
  std::thread th([&] { ex.run(); });
  Client rx;
  client.subscribe("TILLER_WRENCH_VELOCITY", &Client::on_wrench, &rx);
  odometry_t o{};
  double seq = 0;
  auto once = [&] {
    o.position[0] = ++seq;
    client.publish("TILLER_ODOMETRY", &o);
    while (rx.last != seq) {
      if (client.handleTimeout(200) <= 0) return false;  // lost: skip this one
    }
    return true;
  };
  for (int i = 0; i < 100; ++i) once();  // warm-up
  std::int64_t lost = 0;
  for (auto _ : state) {
    if (!once()) ++lost;
  }
  state.counters["lost"] = static_cast<double>(lost);
  ex.stop();
  th.join();
}
BENCHMARK(BM_LiveRoundTrip)->Unit(benchmark::kMicrosecond)->Iterations(5000);

}  // namespace
}  // namespace tiller

BENCHMARK_MAIN();
