// nav_gnss_latency: how long a GNSS fix takes from gpsd to the odometry it changes, through
// the real processes. Run it inside a private network namespace:
//   tools/netns-run build/bench/nav_gnss_latency [SECONDS]     (default 20)
// It starts gpsfake (a real gpsd on 127.0.0.1:29473 fed test/data/gnss/fix_3d.nmea, one
// sentence every 50 ms, so a fix every 0.35 s), tiller-gnss and tiller-nav, and listens itself
// both to gpsd (libgps: the moment gpsd hands out a TPV report, t0) and to LCM: the
// TILLER_GNSS message that carries it (t1) and the first TILLER_ODOMETRY whose north variance
// drops (t2: the filter has taken the fix; between fixes the variance only grows).
// Prints the count and the median, 90th percentile and maximum of t1 - t0 and t2 - t0.
#include <gps.h>
#include <net/if.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
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

struct Sample {
  double t0 = -1, t1 = -1, t2 = -1;
};

struct Listener {
  std::vector<Sample> done;
  Sample cur;
  int incomplete = 0;
  double last_var = -1;
  void on_tpv(double t) {
    if (cur.t0 >= 0) ++incomplete;  // the previous fix never reached the odometry
    cur = Sample{t, -1, -1};
  }
  void on_gnss(const lcm::ReceiveBuffer*, const std::string&, const tiller::gnss_fix_t*) {
    if (cur.t0 >= 0 && cur.t1 < 0) cur.t1 = now_ms();
  }
  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const tiller::odometry_t* o) {
    if (o->n_pose_cov != 36) return;
    const double v = o->pose_covariance[0];
    if (cur.t1 >= 0 && last_var >= 0 && v < last_var) {
      cur.t2 = now_ms();
      done.push_back(cur);
      cur = Sample{};
    }
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
  while (now_ms() - start < warm + seconds * 1000) {
    while (gps_waiting(&gps, 0)) {
      if (gps_read(&gps, nullptr, 0) <= 0) break;
      if ((gps.set & MODE_SET) && gps.fix.mode >= MODE_2D && (gps.set & LATLON_SET)) {
        const double t = now_ms();
        if (t - start > warm) l.on_tpv(t);
        gps.set = 0;
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
  for (const auto& s : l.done) {
    to_gnss.push_back(s.t1 - s.t0);
    to_odom.push_back(s.t2 - s.t0);
  }
  std::printf("nav_gnss_latency: %.0f s of fixes from gpsfake (one per 0.35 s)\n", seconds);
  print("gpsd -> TILLER_GNSS", to_gnss);
  print("gpsd -> TILLER_ODOMETRY", to_odom);
  std::printf("fixes without an odometry change before the next: %d\n", l.incomplete);
  return l.done.empty() ? 1 : 0;
}
