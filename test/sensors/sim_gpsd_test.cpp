// The simulator's NMEA through a REAL gpsd to tiller-gnss's node: a SimNode with the USV's
// simulated sensors writes GGA/GSA/GST/RMC to its pseudo-terminal (lib/sim/nmea_pty.hpp), gpsd
// (started here on that terminal, inside this test's private network namespace) parses them,
// and the GnssNode's fixes must be (1) the simulator's own fixes of the same epoch to the
// NMEA's resolution (1e-7 minute: 0.2 mm) and (2) the true position within the noise
// (2.5 m CEP: 2.12 m per axis).
#include <gtest/gtest.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <tiller/gnss_fix_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/live.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/gpsd_client.hpp"
#include "sim/nmea_pty.hpp"
#include "sim/sim_node.hpp"

extern char** environ;

namespace tiller::sensors {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

struct Fixes : Bus {
  std::string channel;
  std::map<TimeUs, gnss_fix_t> by_time;  // gnss_utime -> fix
  int repeats = 0;                       // fixes of an epoch already published
  explicit Fixes(std::string ch) : channel(std::move(ch)) {}
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    gnss_fix_t m;
    // gpsd's first reports of a new device can come before it has read a time (gnss_utime 0).
    if (ch == channel && m.decode(d, 0, n) == n && m.fix_type != gnss_fix_t::FIX_NONE &&
        m.gnss_utime > 0)
      repeats += !by_time.emplace(m.gnss_utime, m).second;
  }
};

TEST(SimGpsd, TillerGnssFixesThroughGpsdAreTheSimulatorsWithinTheNoise) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/otter.yaml";
  p.initial_nu << 1.5, 0, 0, 0, 0, 0.05;  // gliding forward and turning: course and speed change
  p.initial_eta[5] = 0.5;
  p.sensors = sim::load_sensor_file(kSrc + "/config/sim/sensors/usv.yaml", p.step_us);
  p.sensors.gnss_lcm = p.sensors.gnss_nmea = true;
  SimNode sim(p, load_sim_vehicle_file(p.vehicle_file));
  Fixes simulated(channels::kGnss);
  sim.attach(&simulated);
  sim::NmeaPty pty;
  sim.set_nmea_sink(&pty);

  const char* argv[] = {"gpsd", "-N", "-n", "-b", "-S", "29472", pty.slave_path().c_str(), nullptr};
  pid_t gpsd = -1;
  ASSERT_EQ(posix_spawnp(&gpsd, "gpsd", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
  GnssParams gp;
  gp.port = "29472";
  GnssNode gnss(gp);
  Fixes received("TILLER_GNSS");
  gnss.attach(&received);
  LiveExecutor ex(channels::kDefaultLcmUrl);
  GpsdClient client(gp, gnss, ex);

  std::map<TimeUs, sim::Vector6> truth;  // sim time -> eta
  const TimeUs step = p.step_us;
  TimeUs next = (wall_time_us() / step + 1) * step;
  bool connected = false;
  const TimeUs end = next + 8 * kUsPerSecond;
  while (next < end && received.by_time.size() < 20) {
    while (wall_time_us() < next) usleep(1000);
    sim.tick(next);  // on the step grid: the model is at `next` after the tick
    truth[next] = sim.model().eta();
    if (!connected) connected = client.connect(wall_time_us()).empty();
    if (connected) client.pump(wall_time_us());
    next += step;
  }
  kill(gpsd, SIGTERM);
  waitpid(gpsd, nullptr, 0);
  ASSERT_TRUE(connected) << "gpsd never answered on 127.0.0.1:29472";
  ASSERT_GE(received.by_time.size(), 15u) << "pty " << pty.slave_path() << ", written "
                                          << pty.written() << ", dropped " << pty.dropped();

  // One fix per epoch: libgps keeps a report's `set` bits into the next gps_read, so before the
  // fix every SKY and GST report after a TPV was published as the same fix again (3 per epoch:
  // the estimator fused each fix three times).
  EXPECT_EQ(received.repeats, 0) << received.by_time.size() << " epochs";
  EXPECT_EQ(simulated.repeats, 0);
  const auto& g = p.sensors.gnss;
  GeographicLib::LocalCartesian datum(g.datum_latitude_deg, g.datum_longitude_deg,
                                      g.datum_altitude_m, GeographicLib::Geocentric::WGS84());
  double sum2 = 0;
  int n = 0, early = 0;
  bool whole_cycle = false;  // gpsd has seen a whole cycle: its TPV comes after GST
  for (const auto& [t, f] : received.by_time) {
    const auto s = simulated.by_time.find(t);
    ASSERT_NE(s, simulated.by_time.end()) << "a fix of " << t << " the simulator never made";
    EXPECT_EQ(f.fix_type, gnss_fix_t::FIX_3D);
    EXPECT_NEAR(f.latitude, s->second.latitude, 1e-8);  // 1e-8 deg = 1.1 mm
    EXPECT_NEAR(f.longitude, s->second.longitude, 2e-8);
    EXPECT_NEAR(f.altitude_msl, s->second.altitude_msl, 1e-3);
    EXPECT_NEAR(f.altitude, s->second.altitude, 1e-3);
    EXPECT_NEAR(f.speed, s->second.speed, 1e-3);
    if (f.speed > 0.2) {
      EXPECT_NEAR(f.course, s->second.course, 2e-4);
    }
    EXPECT_EQ(f.satellites, 10);
    // Until gpsd knows the cycle it reports after GGA, before that epoch's GST: gpsd's own
    // error model (ACCURACY_DOP); from then on the receiver's GST deviations, every epoch.
    whole_cycle = whole_cycle || f.accuracy_source == gnss_fix_t::ACCURACY_RECEIVER;
    if (!whole_cycle) {
      EXPECT_EQ(f.accuracy_source, gnss_fix_t::ACCURACY_DOP);
      EXPECT_GT(f.position_std[0], 0.0);
      ++early;
    } else {
      EXPECT_EQ(f.accuracy_source, gnss_fix_t::ACCURACY_RECEIVER);  // GST's deviations
      EXPECT_NEAR(f.position_std[0], g.horizontal_std(), 1e-3);
    }
    double e = 0, no = 0, u = 0;
    datum.Forward(f.latitude, f.longitude, f.altitude, e, no, u);
    const auto tr = truth.find(t);
    ASSERT_NE(tr, truth.end());
    const double err = std::hypot(no - tr->second[0], e - tr->second[1]);
    EXPECT_LT(err, 5 * g.horizontal_std() * std::sqrt(2.0)) << "at " << t;
    sum2 += err * err;
    ++n;
  }
  EXPECT_LE(early, 5) << "epochs before gpsd saw a whole cycle (1 s at 5 Hz)";
  const double rms = std::sqrt(sum2 / n);  // expected sqrt(2) * 2.12 = 3.0 m
  EXPECT_GT(rms, 1.0);
  EXPECT_LT(rms, 5.0);
  std::printf(
      "%d fixes through gpsd (%d before gpsd saw a whole cycle); horizontal error RMS %.2f m "
      "(expected 3.0 m)\n",
      n, early, rms);
}

}  // namespace
}  // namespace tiller::sensors
