// tiller-gnss's node and gpsd client against a REAL gpsd: gpsfake (Debian gpsd-clients) starts
// gpsd on 127.0.0.1 inside this test's private network namespace and feeds it
// test/data/gnss/fix_3d.nmea (hand-written GGA/GSA/GSV/GST/RMC at 59.437 N 10.6612 E, 12.3 m MSL,
// geoid 39.8 m, 9 satellites, HDOP 0.9, 3.00 kn at 45.0 deg, GST 1.5/1.2/2.8 m). The fixes that
// arrive must carry the NMEA's values. Also: no gpsd -> FAULT naming host and port.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <vector>

#include <tiller/gnss_fix_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/live.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/gpsd_client.hpp"

extern char** environ;

namespace tiller::sensors {
namespace {

struct Capture : Bus {
  std::vector<gnss_fix_t> fixes;
  heartbeat_t hb;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    if (ch == "TILLER_GNSS") {
      gnss_fix_t m;
      if (m.decode(d, 0, n) == n) fixes.push_back(m);
    } else if (ch == "TILLER_HEARTBEAT_GNSS") {
      hb.decode(d, 0, n);
    }
  }
};

pid_t spawn(std::vector<const char*> argv) {
  argv.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(posix_spawnp(&pid, argv[0], nullptr, nullptr, const_cast<char**>(argv.data()), environ),
            0);
  return pid;
}

TEST(GnssGpsd, FixesFromARealGpsdCarryTheNmeaValues) {
  const pid_t fake = spawn({"gpsfake", "-1", "-q", "-c", "0.1", "-P", "29471",
                            TILLER_SOURCE_DIR "/test/data/gnss/fix_3d.nmea"});
  GnssParams p;
  p.port = "29471";
  GnssNode node(p);
  LiveExecutor ex(channels::kDefaultLcmUrl);
  Capture out;
  GpsdClient client(p, node, ex);
  node.attach(&out);
  std::string why = "not tried";
  for (int i = 0; i < 200 && !why.empty(); ++i) {
    why = client.connect(wall_time_us());
    if (!why.empty()) usleep(50'000);
  }
  ASSERT_EQ(why, "");
  auto full = [&] {  // fixes with every sentence of their epoch seen (GST, SKY before TPV)
    int n = 0;
    for (const auto& f : out.fixes)
      n += f.accuracy_source == gnss_fix_t::ACCURACY_RECEIVER && f.velocity_valid;
    return n;
  };
  for (int i = 0; i < 400 && full() < 3; ++i) {
    client.pump(wall_time_us());
    usleep(20'000);
  }
  kill(fake, SIGTERM);
  waitpid(fake, nullptr, 0);
  ASSERT_GE(full(), 3);
  const gnss_fix_t& f = out.fixes.back();
  EXPECT_EQ(f.fix_type, gnss_fix_t::FIX_3D);
  EXPECT_NEAR(f.latitude, 59.0 + 26.22 / 60, 1e-9);    // 5926.2200 N
  EXPECT_NEAR(f.longitude, 10.0 + 39.672 / 60, 1e-9);  // 01039.6720 E
  EXPECT_NEAR(f.altitude_msl, 12.3, 1e-9);
  EXPECT_NEAR(f.altitude, 12.3 + 39.8, 1e-9);  // ellipsoid = MSL + geoid separation
  EXPECT_EQ(f.satellites, 9);                  // GSA lists 9 PRNs, GGA says 09
  EXPECT_NEAR(f.hdop, 0.9, 1e-9);
  EXPECT_TRUE(f.velocity_valid);
  EXPECT_NEAR(f.speed, 3.00 * 1852.0 / 3600.0, 1e-3);  // 3.00 kn
  EXPECT_NEAR(f.course, 45.0 * M_PI / 180.0, 1e-9);
  EXPECT_EQ(f.accuracy_source, gnss_fix_t::ACCURACY_RECEIVER);  // from GST
  EXPECT_NEAR(f.position_std[0], 1.5, 1e-9);
  EXPECT_NEAR(f.position_std[1], 1.2, 1e-9);
  EXPECT_NEAR(f.position_std[2], 2.8, 1e-9);
  // 2026-12-01 12:00:0s UTC
  EXPECT_EQ((f.gnss_utime / 1'000'000 - 1'796'126'400) / 60, 0) << f.gnss_utime;
  EXPECT_EQ(f.gnss_utime % 1'000'000, 0);
  EXPECT_EQ(node.counter_value("fixes"), static_cast<std::int64_t>(out.fixes.size()));
  // The pilot's view (issue 31): fix type, satellites, HDOP and the 1-sigma error in the heartbeat.
  node.tick(wall_time_us());
  EXPECT_EQ(out.hb.state, heartbeat_t::STATE_OK);
  EXPECT_NE(out.hb.status.find("3D fix, 9 satellites, HDOP 0.9, 1.5 m 1-sigma (receiver GST)"),
            std::string::npos)
      << out.hb.status;
  // One message per epoch (the file has 5, 1 s apart), in time order: a report that is not a TPV
  // (SKY, GST) is not published as the last fix again.
  TimeUs last = 0;
  for (const auto& x : out.fixes) {
    if (x.gnss_utime == 0) continue;  // gpsd's first reports, before it has read a time
    EXPECT_GT(x.gnss_utime, last) << "fix of epoch " << x.gnss_utime << " published again";
    last = x.gnss_utime;
  }
}

TEST(GnssGpsd, NoGpsdIsFaultNamingHostAndPort) {
  GnssParams p;
  p.port = "29479";  // nothing listens
  GnssNode node(p);
  LiveExecutor ex(channels::kDefaultLcmUrl);
  Capture out;
  node.attach(&out);
  GpsdClient client(p, node, ex);
  const std::string why = client.connect(wall_time_us());
  EXPECT_NE(why.find("cannot connect to gpsd at 127.0.0.1:29479"), std::string::npos) << why;
  node.tick(0);
  EXPECT_EQ(out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(out.hb.status.find("127.0.0.1:29479"), std::string::npos) << out.hb.status;
  EXPECT_TRUE(out.fixes.empty());
}

}  // namespace
}  // namespace tiller::sensors
