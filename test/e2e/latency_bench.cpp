// Latency from a stick event to the ESC write across tiller-teleop -> tiller-mixer -> tiller-esc,
// next to three bare LCM hops through three bench_relay processes of the same shape, measured in
// the same run (blocks interleaved so that machine load affects both alike).
//   t0: CLOCK_REALTIME just before the js_event is written into the FIFO the teleop reads
//   t1: CLOCK_REALTIME when this process receives the first TILLER_ESC_OUTPUT carrying the new
//       throttle (the sim backend publishes exactly what it writes to the bus, when it writes it)
// Same clock, same host, same private network namespace. Prints p50/p90/p99/max.
// Run by hand:  tools/netns-run build/bench/teleop_latency_bench [--events N]
// (--smoke: 200 events, used by ctest as a functional check; it asserts no timing.)
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "e2e_config.hpp"
#include "e2e_util.hpp"

using namespace tiller;
using namespace tiller::e2e;

namespace {

struct Rx {
  void on_esc(const lcm::ReceiveBuffer*, const std::string&, const esc_output_t* m) {
    t_esc = realtime_us();
    t1 = m->n_channels > 0 ? m->value[0] : 0;
    armed = m->armed;
    ++n_esc;
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) {
    arm = m->armed;
  }
  void on_demand(const lcm::ReceiveBuffer*, const std::string&, const manual_demand_t* m) {
    valid = m->valid;
    if (m->demand[0] != d0) {
      d0 = m->demand[0];
      t_demand = realtime_us();
    }
  }
  void on_cmd(const lcm::ReceiveBuffer*, const std::string&, const thruster_command_t* m) {
    const double c = m->n_thrusters > 0 ? m->command[0] : 0.0;
    if (c != c0) {
      c0 = c;
      t_cmd = realtime_us();
    }
  }
  void on_bare(const lcm::ReceiveBuffer*, const std::string&) {
    t_bare = realtime_us();
    ++n_bare;
  }
  std::int64_t t_esc = 0, t_bare = 0, t_demand = 0, t_cmd = 0;
  double d0 = 0, c0 = 0;
  int t1 = 0;
  bool armed = false, arm = false, valid = false;
  long n_esc = 0, n_bare = 0;
};

template <class Pred>
bool pump(lcm::LCM& l, Pred pred, double seconds) {
  const std::int64_t end = realtime_us() + static_cast<std::int64_t>(seconds * 1e6);
  while (realtime_us() < end) {
    if (pred()) return true;
    l.handleTimeout(2);
  }
  return pred();
}

void report(const char* what, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto q = [&](double p) {
    return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
  };
  std::printf("%-38s n=%6zu  min %7.1f  p50 %7.1f  p90 %7.1f  p99 %7.1f  max %8.1f us\n", what,
              v.size(), v.front(), q(0.5), q(0.9), q(0.99), v.back());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int n_events = 10000;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--smoke") n_events = 200;
    if (a == "--events" && i + 1 < argc) n_events = std::atoi(argv[++i]);
  }
  lcm::LCM l(kUrl);
  if (!l.good()) {
    std::fprintf(stderr, "LCM not available: run under tools/netns-run\n");
    return 1;
  }
  Rx rx;
  l.subscribe("TILLER_ESC_OUTPUT", &Rx::on_esc, &rx);
  l.subscribe("TILLER_ARM_STATE", &Rx::on_arm, &rx);
  l.subscribe("TILLER_MANUAL_DEMAND", &Rx::on_demand, &rx);
  l.subscribe("TILLER_THRUSTER_COMMAND", &Rx::on_cmd, &rx);
  l.subscribe("BENCH_BARE_3", &Rx::on_bare, &rx);

  const std::string src = TILLER_SOURCE_DIR, bin = TILLER_BIN_DIR;
  const std::string tag = std::to_string(getpid());
  FifoStick stick("/tmp/tiller_bench_js_" + tag);
  FifoStick bare("/tmp/tiller_bench_bare_" + tag);
  bare.plug();
  stick.plug();
  stick.init({0, 0, 0, 32767, 0, 0});
  const std::string relay = std::string(TILLER_BENCH_DIR) + "/bench_relay";
  Proc r3(relay, {"lcm", "BENCH_BARE_2", "BENCH_BARE_3", kUrl});
  Proc r2(relay, {"lcm", "BENCH_BARE_1", "BENCH_BARE_2", kUrl});
  Proc r1(relay, {"fifo", bare.path(), "BENCH_BARE_1", kUrl});
  Proc esc(bin + "/tiller-esc", {"--config", src + "/" + kEscConfig, "--lcm-url", kUrl});
  Proc mixer(bin + "/tiller-mixer", {"--config", src + "/" + kMixerConfig, "--lcm-url", kUrl});
  Proc teleop(bin + "/tiller-teleop", {"--config", src + "/config/teleop/extreme3dpro_seed000.yaml",
                                       "--device", stick.path(), "--lcm-url", kUrl});
  if (!pump(
          l, [&] { return rx.valid && rx.n_esc > 10; }, 5.0)) {
    std::fprintf(stderr, "the stack did not come up (teleop valid %d, esc outputs %ld)\n", rx.valid,
                 rx.n_esc);
    return 1;
  }
  stick.button(6, true);
  e2e::sleep_ms(100);
  stick.button(6, false);
  if (!pump(
          l, [&] { return rx.arm && rx.armed; }, 3.0)) {
    std::fprintf(stderr, "could not arm\n");
    return 1;
  }
  // Warm up both chains.
  bare.write({JsEvent{0, 0, kJsEventAxis, 1}});
  if (!pump(
          l, [&] { return rx.n_bare > 0; }, 3.0)) {
    std::fprintf(stderr, "bare relay chain did not come up\n");
    return 1;
  }

  std::mt19937 rng(1234);
  // Gaps spread over more than one ESC period (10 ms), so events do not lock to its tick phase.
  std::uniform_real_distribution<double> gap_ms(1.0, 12.0);
  std::vector<double> tiller_us, bare_us, demand_us, cmd_us;
  tiller_us.reserve(static_cast<std::size_t>(n_events));
  bare_us.reserve(static_cast<std::size_t>(n_events));
  const int positions[2] = {-32767, -24000};  // both forward; distinct throttles
  int k = 0;
  long lost_tiller = 0, lost_bare = 0;
  const int block = 250;
  while (static_cast<int>(tiller_us.size()) < n_events ||
         static_cast<int>(bare_us.size()) < n_events) {
    for (int i = 0; i < block && static_cast<int>(tiller_us.size()) < n_events; ++i) {
      const int before = rx.t1;
      const std::int64_t t0 = stick.axis(1, positions[k++ % 2]);
      if (pump(
              l, [&] { return rx.t1 != before; }, 0.5)) {
        tiller_us.push_back(static_cast<double>(rx.t_esc - t0));
        if (rx.t_demand >= t0) demand_us.push_back(static_cast<double>(rx.t_demand - t0));
        if (rx.t_cmd >= t0) cmd_us.push_back(static_cast<double>(rx.t_cmd - t0));
      } else {
        ++lost_tiller;
      }
      e2e::sleep_ms(gap_ms(rng));
    }
    for (int i = 0; i < block && static_cast<int>(bare_us.size()) < n_events; ++i) {
      const long before = rx.n_bare;
      const std::int64_t t0 =
          bare.write({JsEvent{0, static_cast<std::int16_t>(i), kJsEventAxis, 1}});
      if (pump(
              l, [&] { return rx.n_bare != before; }, 0.5)) {
        bare_us.push_back(static_cast<double>(rx.t_bare - t0));
      } else {
        ++lost_bare;
      }
      e2e::sleep_ms(gap_ms(rng));
    }
  }
  std::printf("stick event -> ESC write latency, %d events each, CLOCK_REALTIME, one namespace\n",
              n_events);
  report("three bare LCM hops (FIFO+3 procs)", bare_us);
  report("tiller teleop -> mixer -> esc", tiller_us);
  if (!demand_us.empty()) report("  of which: event -> MANUAL_DEMAND", demand_us);
  if (!cmd_us.empty()) report("  of which: event -> THRUSTER_COMMAND", cmd_us);
  const double mb = median(bare_us), mt = median(tiller_us);
  std::printf("Tiller adds %.1f%% to the bare hops at p50 (%.1f us vs %.1f us); target < 20%%\n",
              100.0 * (mt - mb) / mb, mt, mb);
  if (lost_tiller + lost_bare > 0) {
    std::printf("timeouts (no answer within 0.5 s): tiller %ld, bare %ld\n", lost_tiller,
                lost_bare);
  }
  return tiller_us.empty() || bare_us.empty() ? 1 : 0;
}
