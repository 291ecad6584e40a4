// Missed ticks and the largest gap between ESC outputs with every core busy (stress-ng), for
// tiller-esc (sim backend) + tiller-mixer fed by tiller-teleop (a FIFO joystick moved every
// 20 ms, armed), first on the normal scheduler, then with SCHED_FIFO and locked memory
// (--realtime-priority 45 / 40 --lock-memory, as the real-vehicle launch files ask).
//   ticks missed: from the heartbeats, ticks.missed / (ticks.run + ticks.missed) over the window
//   ESC write gaps: between the utime of consecutive TILLER_ESC_OUTPUT, the grid time of each
//     bus write (a late tick is told the latest grid point it reached, so within one 2 ms tick
//     of when it wrote): what the ESCs saw
//   ESC output gaps as received: CLOCK_REALTIME here between the same messages; adds the
//     loopback network path, whose softirq work runs at normal priority (ksoftirqd) under load.
//     This process runs at SCHED_FIFO 60 (reset on fork) when permitted, so its own waiting
//     stays out of it.
// Prints figures; asserts nothing. Run it where SCHED_FIFO is permitted inside the namespace:
//   tools/netns-run --root build/bench/realtime_bench [--seconds S] [--stress-workers N]
// (under plain tools/netns-run, a user namespace, the SCHED_FIFO case is refused and says so).
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "e2e_config.hpp"
#include "e2e_util.hpp"

using namespace tiller;
using namespace tiller::e2e;

namespace {

struct Rx {
  void on_esc(const lcm::ReceiveBuffer*, const std::string&, const esc_output_t* m) {
    const std::int64_t t = realtime_us();
    if (recording) {
      times.push_back(t);
      stamps.push_back(m->utime);
    }
    armed = m->armed;
    ++n_esc;
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) {
    arm = m->armed;
  }
  void on_demand(const lcm::ReceiveBuffer*, const std::string&, const manual_demand_t* m) {
    valid = m->valid;
  }
  void on_heartbeat(const lcm::ReceiveBuffer*, const std::string& ch, const heartbeat_t* m) {
    auto& c = counters[ch];
    for (int i = 0; i < m->n_counters; ++i) c[m->counter_names[i]] = m->counter_values[i];
  }
  std::int64_t get(const std::string& ch, const std::string& name) {
    return counters[ch].count(name) ? counters[ch][name] : 0;
  }
  std::vector<std::int64_t> times, stamps;  // receive time here; the ESC's own utime
  bool recording = false, armed = false, arm = false, valid = false;
  long n_esc = 0;
  std::map<std::string, std::map<std::string, std::int64_t>> counters;
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

double loadavg() {
  std::ifstream in("/proc/loadavg");
  double one = 0;
  in >> one;
  return one;
}

// The "real time:" lines a program printed at start.
void print_realtime_lines(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.find("real time:") != std::string::npos) std::printf("    %s\n", line.c_str());
}

struct Ticks {
  std::int64_t run = 0, missed = 0;
};
Ticks ticks(Rx& rx, const std::string& ch) {
  return {rx.get(ch, "ticks.run"), rx.get(ch, "ticks.missed")};
}
double missed_pct(const Ticks& a, const Ticks& b) {
  const double run = static_cast<double>(b.run - a.run),
               missed = static_cast<double>(b.missed - a.missed);
  return run + missed > 0 ? 100.0 * missed / (run + missed) : 0.0;
}

// Gaps between consecutive times (us), in ms: percentiles and the counts over three bounds.
void print_gaps(const char* what, const std::vector<std::int64_t>& t) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < t.size(); ++i)
    gaps.push_back(static_cast<double>(t[i] - t[i - 1]) / 1000.0);
  if (gaps.empty()) return;
  std::sort(gaps.begin(), gaps.end());
  auto q = [&](double p) {
    return gaps[static_cast<std::size_t>(p * static_cast<double>(gaps.size() - 1))];
  };
  auto over = [&](double ms) {
    return static_cast<long>(gaps.end() - std::upper_bound(gaps.begin(), gaps.end(), ms));
  };
  std::printf(
      "  %-34s ms: p50 %6.2f  p99 %6.2f  p99.9 %6.2f  max %6.1f;  > 20 ms: %ld, "
      "> 100 ms: %ld, > 250 ms (command timeout): %ld\n",
      what, q(0.5), q(0.99), q(0.999), gaps.back(), over(20), over(100), over(250));
}

struct Options {
  double seconds = 30;
  int workers = 0;  // 0: 4 per core
  int esc_priority = 45, mixer_priority = 40;
  std::vector<std::string> cases = {"normal", "fifo"};
};

// One case: start the three processes, arm, move the stick for o.seconds, print the figures.
bool run_case(lcm::LCM& l, Rx& rx, const Options& o, bool fifo) {
  const std::string src = TILLER_SOURCE_DIR, bin = TILLER_BIN_DIR;
  const std::string tag = std::to_string(getpid()) + (fifo ? "_fifo" : "_normal");
  std::vector<std::string> esc_args{"--config", src + "/" + kEscConfig, "--lcm-url", kUrl};
  std::vector<std::string> mixer_args{"--config", src + "/" + kMixerConfig, "--lcm-url", kUrl};
  if (fifo) {
    for (auto* a : {&esc_args, &mixer_args}) a->push_back("--lock-memory");
    esc_args.push_back("--realtime-priority=" + std::to_string(o.esc_priority));
    mixer_args.push_back("--realtime-priority=" + std::to_string(o.mixer_priority));
  }
  rx = Rx{};
  FifoStick stick("/tmp/tiller_rtbench_js_" + tag);
  stick.plug();
  stick.init({0, 0, 0, 32767, 0, 0});
  const std::string esc_out = "/tmp/tiller_rtbench_esc_" + tag + ".txt";
  const std::string mixer_out = "/tmp/tiller_rtbench_mixer_" + tag + ".txt";
  Proc esc(bin + "/tiller-esc", esc_args, true, esc_out);
  Proc mixer(bin + "/tiller-mixer", mixer_args, true, mixer_out);
  Proc teleop(bin + "/tiller-teleop", {"--config", src + "/config/teleop/extreme3dpro_seed000.yaml",
                                       "--device", stick.path(), "--lcm-url", kUrl});
  std::printf("\n%s: tiller-esc and tiller-mixer %s\n", fifo ? "fifo" : "normal",
              fifo ? "with --realtime-priority 45 / 40 --lock-memory" : "on the normal scheduler");
  if (!pump(
          l, [&] { return rx.valid && rx.n_esc > 10; }, 20.0)) {
    std::fprintf(stderr, "the stack did not come up (teleop valid %d, esc outputs %ld)\n", rx.valid,
                 rx.n_esc);
    return false;
  }
  stick.button(6, true);
  sleep_ms(100);
  stick.button(6, false);
  if (!pump(
          l, [&] { return rx.arm; }, 10.0)) {
    std::fprintf(stderr, "could not arm\n");
    return false;
  }
  print_realtime_lines(esc_out);
  print_realtime_lines(mixer_out);
  const std::string hb_esc = "TILLER_HEARTBEAT_ESC", hb_mixer = "TILLER_HEARTBEAT_MIXER";
  // The window starts at a heartbeat of each, so the tick counts cover it exactly.
  rx.counters.clear();
  pump(
      l, [&] { return rx.counters.count(hb_esc) && rx.counters.count(hb_mixer); }, 5.0);
  const Ticks esc0 = ticks(rx, hb_esc), mixer0 = ticks(rx, hb_mixer);
  const double load0 = loadavg();
  rx.recording = true;
  const std::int64_t end = realtime_us() + static_cast<std::int64_t>(o.seconds * 1e6);
  std::int64_t next_move = realtime_us();
  int k = 0;
  const int positions[2] = {-32767, -24000};  // forward, two throttles: a new command each time
  while (realtime_us() < end) {
    if (realtime_us() >= next_move) {
      stick.axis(1, positions[k++ % 2]);
      next_move += 20'000;
    }
    l.handleTimeout(2);
  }
  rx.recording = false;
  // The last heartbeat of each inside the window.
  const Ticks esc1 = ticks(rx, hb_esc), mixer1 = ticks(rx, hb_mixer);
  const std::int64_t esc_prio = rx.get(hb_esc, "realtime.priority");
  const std::int64_t mixer_prio = rx.get(hb_mixer, "realtime.priority");
  std::printf(
      "  load average %.1f -> %.1f; SCHED_FIFO in force (heartbeats): esc %lld, mixer %lld\n",
      load0, loadavg(), static_cast<long long>(esc_prio), static_cast<long long>(mixer_prio));
  std::printf(
      "  ticks missed: esc %.2f %% (%lld of %lld grid points), mixer %.2f %% (%lld of %lld)\n",
      missed_pct(esc0, esc1), static_cast<long long>(esc1.missed - esc0.missed),
      static_cast<long long>(esc1.run - esc0.run + esc1.missed - esc0.missed),
      missed_pct(mixer0, mixer1), static_cast<long long>(mixer1.missed - mixer0.missed),
      static_cast<long long>(mixer1.run - mixer0.run + mixer1.missed - mixer0.missed));
  std::printf("  %zu ESC outputs in %.0f s\n", rx.times.size(), o.seconds);
  print_gaps("ESC write gaps (output utime)", rx.stamps);
  print_gaps("ESC output gaps as received here", rx.times);
  std::remove(esc_out.c_str());
  std::remove(mixer_out.c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each figure as soon as it is known
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seconds" && i + 1 < argc) o.seconds = std::atof(argv[++i]);
    if (a == "--stress-workers" && i + 1 < argc) o.workers = std::atoi(argv[++i]);
    if (a == "--cases" && i + 1 < argc) {
      o.cases.clear();
      std::stringstream s(argv[++i]);
      for (std::string c; std::getline(s, c, ',');) o.cases.push_back(c);
    }
  }
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (o.workers <= 0) o.workers = static_cast<int>(4 * cores);
  lcm::LCM l(kUrl);
  if (!l.good()) {
    std::fprintf(stderr, "LCM not available: run under tools/netns-run --root\n");
    return 1;
  }
  Rx rx;
  l.subscribe("TILLER_ESC_OUTPUT", &Rx::on_esc, &rx);
  l.subscribe("TILLER_ARM_STATE", &Rx::on_arm, &rx);
  l.subscribe("TILLER_MANUAL_DEMAND", &Rx::on_demand, &rx);
  l.subscribe("TILLER_HEARTBEAT_ESC", &Rx::on_heartbeat, &rx);
  l.subscribe("TILLER_HEARTBEAT_MIXER", &Rx::on_heartbeat, &rx);
  // The measuring end above both, when permitted. SCHED_RESET_ON_FORK: the processes started
  // from here (stress-ng, the stack) begin on the normal scheduler, not at this priority.
  sched_param sp{};
  sp.sched_priority = 60;
  const bool self_fifo = sched_setscheduler(0, SCHED_FIFO | SCHED_RESET_ON_FORK, &sp) == 0;
  if (self_fifo) mlockall(MCL_CURRENT | MCL_FUTURE);
  std::printf("realtime_bench: %ld cores, stress-ng --cpu %d, %.0f s per case; this process: %s\n",
              cores, o.workers, o.seconds,
              self_fifo ? "SCHED_FIFO 60 (its own waiting stays out of the gaps)"
                        : "normal scheduler (SCHED_FIFO refused: the gaps include its own waits)");
  Proc stress("/usr/bin/stress-ng", {"--cpu", std::to_string(o.workers), "--quiet"});
  sleep_ms(3000);
  bool ok = true;
  for (const auto& c : o.cases) ok = run_case(l, rx, o, c == "fifo") && ok;
  return ok ? 0 : 1;
}
