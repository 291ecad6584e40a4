// nav_gnss_latency: how long a GNSS fix takes from gpsd to the odometry it changes, through
// the real processes. Run it inside a private network namespace:
//   tools/netns-run build/bench/nav_gnss_latency [SECONDS]     (default 20)
// It starts gpsfake (a real gpsd on 127.0.0.1:29473 fed test/data/gnss/fix_3d.nmea, one
// sentence every 50 ms, so a fix every 0.35 s), tiller-gnss and tiller-nav, and listens itself
// both to gpsd (libgps: the moment gpsd hands out a TPV report, t0) and to LCM: the
// TILLER_GNSS message that carries it (t1) and the first TILLER_ODOMETRY whose north variance
// drops (t2: the filter has taken the fix; between fixes the variance only grows).
// Prints the count and the median, 90th percentile and maximum of t1 - t0 and t2 - t0. Only the
// first TPV of an epoch is timed: gpsd may send a second one with the same fix time, which
// tiller-gnss does not publish (one fix per epoch).
#include <gps.h>
#include <net/if.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/odometry_t.hpp>

extern char** environ;

namespace {

double now_ms() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

pid_t spawn(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) {
    std::fprintf(stderr, "nav_gnss_latency: cannot start %s\n", argv[0]);
    std::exit(2);
  }
  return pid;
}

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
}

// What the tool saw, each with its arrival time (ms, steady clock). Matched after the run: a fix
// (gpsd's TPV, by its fix time) to the TILLER_GNSS that carries it (the same gnss_utime, within
// 300 ms: the test file's epochs repeat when gpsfake loops) and to the first odometry after
// both whose north variance dropped. Both clients read the same gpsd report, so TILLER_GNSS can
// arrive before this tool has read its own copy: that latency is then below 0 (printed as is).
struct Listener {
  std::vector<std::pair<double, std::int64_t>> tpv, gnss;  // (arrival, fix time us)
  std::vector<double> drops;                               // odometry whose variance dropped
  double last_var = -1;
  void on_gnss(const lcm::ReceiveBuffer*, const std::string&, const tiller::gnss_fix_t* m) {
    gnss.emplace_back(now_ms(), m->gnss_utime);
  }
  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const tiller::odometry_t* o) {
    if (o->n_pose_cov != 36) return;
    const double v = o->pose_covariance[0];
    if (last_var >= 0 && v < last_var) drops.push_back(now_ms());
    last_var = v;
  }
};

void print(const char* what, std::vector<double> v) {
  if (v.empty()) {
    std::printf("%-28s no samples\n", what);
    return;
  }
  std::sort(v.begin(), v.end());
  std::printf("%-28s median %.2f ms, p90 %.2f ms, max %.2f ms (%zu fixes)\n", what, v[v.size() / 2],
              v[v.size() * 9 / 10], v.back(), v.size());
}

// True when the only network interface is the loopback (a private namespace, tools/netns-run):
// the processes this tool starts open LCM on their default udpm:// URL.
bool only_loopback() {
  struct if_nameindex* ifs = if_nameindex();  // of this process's network namespace
  if (ifs == nullptr) return false;
  bool only_lo = true;
  for (const struct if_nameindex* i = ifs; i->if_index != 0; ++i)
    only_lo = only_lo && std::string(i->if_name) == "lo";
  if_freenameindex(ifs);
  return only_lo;
}

}  // namespace

int main(int argc, char** argv) {
  if (!only_loopback()) {
    std::fprintf(stderr,
                 "nav_gnss_latency: this network namespace has interfaces besides lo; run it "
                 "under tools/netns-run (LCM traffic must not leave the machine)\n");
    return 2;
  }
  const double seconds = argc > 1 ? std::atof(argv[1]) : 20.0;
  const std::string src = TILLER_SOURCE_DIR, bin = TILLER_BIN_DIR;
  const std::string port = "29473";
  const std::string gnss_cfg = "/tmp/nav_gnss_latency_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(gnss_cfg) << "gpsd_host: 127.0.0.1\ngpsd_port: " << port
                          << "\nstale_after_s: 2.0\nreconnect_period_s: 0.2\n";
  const pid_t fake =
      spawn({"gpsfake", "-q", "-c", "0.05", "-P", port, src + "/test/data/gnss/fix_3d.nmea"});
  lcm::LCM lc("udpm://239.255.76.67:7667?ttl=0");
  if (!lc.good()) {
    std::fprintf(stderr, "nav_gnss_latency: no LCM (run it under tools/netns-run)\n");
    stop(fake);
    return 2;
  }
  Listener l;
  lc.subscribe("TILLER_GNSS", &Listener::on_gnss, &l);
  lc.subscribe("TILLER_ODOMETRY", &Listener::on_odometry, &l);
  gps_data_t gps{};
  bool open = false;
  for (int i = 0; i < 100 && !open; ++i) {
    open = gps_open("127.0.0.1", port.c_str(), &gps) == 0;
    if (!open) usleep(100'000);
  }
  if (!open) {
    std::fprintf(stderr, "nav_gnss_latency: gpsfake's gpsd did not come up on %s\n", port.c_str());
    stop(fake);
    return 2;
  }
  gps_stream(&gps, WATCH_ENABLE | WATCH_JSON, nullptr);
  const pid_t gnss = spawn({bin + "/tiller-gnss", "--config", gnss_cfg});
  const pid_t nav = spawn({bin + "/tiller-nav", "--config", src + "/config/nav/usv.yaml"});
  const double start = now_ms(), warm = 3000;
  timespec last{};  // the fix time of the last TPV: tiller-gnss publishes one per epoch
  int repeats = 0;
  while (now_ms() - start < warm + seconds * 1000) {
    while (gps_waiting(&gps, 0)) {
      gps.set = 0;  // libgps keeps the last report's bits: cleared, only a TPV sets MODE_SET
      if (gps_read(&gps, nullptr, 0) <= 0) break;
      if ((gps.set & MODE_SET) && gps.fix.mode >= MODE_2D && (gps.set & LATLON_SET)) {
        const bool repeat =
            gps.fix.time.tv_sec == last.tv_sec && gps.fix.time.tv_nsec == last.tv_nsec;
        last = gps.fix.time;
        const double t = now_ms();
        if (t - start <= warm) continue;
        if (repeat) {
          ++repeats;
        } else {
          l.tpv.emplace_back(t, static_cast<std::int64_t>(gps.fix.time.tv_sec) * 1'000'000 +
                                    gps.fix.time.tv_nsec / 1000);
        }
      }
    }
    lc.handleTimeout(1);
  }
  stop(nav);
  stop(gnss);
  gps_close(&gps);
  stop(fake);
  std::remove(gnss_cfg.c_str());
  std::vector<double> to_gnss, to_odom;
  int unmatched = 0;
  for (const auto& [t0, fix] : l.tpv) {
    double t1 = -1e9;
    for (const auto& [t, g] : l.gnss)
      if (g == fix && std::abs(t - t0) < 300 && std::abs(t - t0) < std::abs(t1 - t0)) t1 = t;
    const auto d = std::lower_bound(l.drops.begin(), l.drops.end(), std::max(t0, t1));
    if (t1 < -1e8 || d == l.drops.end() || *d - t0 > 300) {
      ++unmatched;
      continue;
    }
    to_gnss.push_back(t1 - t0);
    to_odom.push_back(*d - t0);
  }
  std::printf("nav_gnss_latency: %.0f s of fixes from gpsfake (one per 0.35 s)\n", seconds);
  print("gpsd -> TILLER_GNSS", to_gnss);
  print("gpsd -> TILLER_ODOMETRY", to_odom);
  std::printf("fixes without their TILLER_GNSS or odometry change within 300 ms: %d\n", unmatched);
  std::printf("TPV reports of an epoch already timed (tiller-gnss drops them): %d\n", repeats);
  return to_odom.empty() ? 1 : 0;
}
