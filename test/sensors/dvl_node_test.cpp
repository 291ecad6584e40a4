// DvlNode (lib/sensors/dvl_node.hpp) with hand-computed numbers: the mounting rotation of the
// velocity and its covariance, the latency, no-lock messages, lock loss and regain, malformed and
// invalid lines counted with nothing published, the timeout and link FAULTs, the heartbeat text;
// and the strict config loader.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <tiller/dvl_t.hpp>
#include <tiller/heartbeat_t.hpp>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "sensors/dvl_node.hpp"

namespace tiller::sensors {
namespace {

struct Capture : Bus {
  std::vector<dvl_t> dvl;
  heartbeat_t heartbeat;
  int heartbeats = 0;
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    if (channel == "TILLER_DVL") {
      dvl_t m;
      EXPECT_EQ(m.decode(data, 0, size), size);
      dvl.push_back(m);
    } else if (channel == "TILLER_HEARTBEAT_DVL") {
      EXPECT_EQ(heartbeat.decode(data, 0, size), size);
      ++heartbeats;
    }
  }
};

std::string velocity_line(double vx, double vy, double vz, double fom, double altitude, bool valid,
                          int status, const std::string& extra = "") {
  char b[512];
  std::snprintf(
      b, sizeof b,
      R"({"time": 100.0, "vx": %g, "vy": %g, "vz": %g, "fom": %g, "altitude": %g,)"
      R"( "velocity_valid": %s, "status": %d%s, "format": "json_v3.1", "type": "velocity"})",
      vx, vy, vz, fom, altitude, valid ? "true" : "false", status, extra.c_str());
  return b;
}

// The heartbeat's status after a tick at `t` (a whole second, so one is published).
std::string status_at(DvlNode& n, Capture& c, TimeUs t) {
  n.tick(t);
  return c.heartbeat.status;
}

TEST(DvlNode, AYaw90MountingRotatesVelocityAndCovariance) {
  DvlParams p;
  p.yaw = M_PI / 2;  // the DVL's x is the body's y (turned to starboard)
  p.latency_s = 0.2;
  DvlNode n(p);
  Capture c;
  n.attach(&c);
  n.set_link(true, "", 0);
  // Covariance diag(1e-4, 4e-4, 9e-4) and one off-diagonal term 2e-5 (x, y).
  n.feed(velocity_line(0.1, 0.02, -0.01, 0.004, 3.2, true, 0,
                       R"(, "covariance": [[1e-4, 2e-5, 0], [2e-5, 4e-4, 0], [0, 0, 9e-4]])"),
         1'000'000);
  ASSERT_EQ(c.dvl.size(), 1u);
  const dvl_t& m = c.dvl[0];
  EXPECT_EQ(m.utime, 800'000);  // 1 s - 0.2 s
  EXPECT_TRUE(m.bottom_lock);
  // Rz(90): [u v w] = [-vy, vx, vz]
  EXPECT_NEAR(m.velocity[0], -0.02, 1e-12);
  EXPECT_NEAR(m.velocity[1], 0.1, 1e-12);
  EXPECT_NEAR(m.velocity[2], -0.01, 1e-12);
  // R C R^T with R = [[0 -1 0] [1 0 0] [0 0 1]]: diag(4e-4, 1e-4, 9e-4), xy term -2e-5.
  EXPECT_NEAR(m.velocity_covariance[0], 4e-4, 1e-15);
  EXPECT_NEAR(m.velocity_covariance[4], 1e-4, 1e-15);
  EXPECT_NEAR(m.velocity_covariance[8], 9e-4, 1e-15);
  EXPECT_NEAR(m.velocity_covariance[1], -2e-5, 1e-15);
  EXPECT_EQ(m.velocity_covariance[1], m.velocity_covariance[3]);
  EXPECT_NEAR(m.velocity_covariance[2], 0, 1e-15);
  EXPECT_DOUBLE_EQ(m.fom, 0.004);
  EXPECT_DOUBLE_EQ(m.altitude, 3.2);
  EXPECT_EQ(m.beams_valid, -1);
  EXPECT_EQ(m.sensor, "dvl-a50@192.168.194.95:16171");
  EXPECT_EQ(checks::check(m), nullptr);
  EXPECT_EQ(status_at(n, c, 1'000'000), "bottom lock, altitude 3.2 m, fom 0.004 m/s");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_OK);
}

TEST(DvlNode, DefaultMountingAndFomCovariance) {
  DvlNode n{DvlParams{}};
  Capture c;
  n.attach(&c);
  n.set_link(true, "", 0);
  // json_v2: no covariance -> diag(fom^2); no latency; beams counted.
  n.feed(velocity_line(0.3, -0.1, 0.05, 0.01, 1.5, true, 0,
                       R"(, "transducers": [{"beam_valid": true}, {"beam_valid": true},)"
                       R"( {"beam_valid": false}, {"beam_valid": true}])"),
         500'000);
  ASSERT_EQ(c.dvl.size(), 1u);
  const dvl_t& m = c.dvl[0];
  EXPECT_EQ(m.utime, 500'000);
  EXPECT_DOUBLE_EQ(m.velocity[0], 0.3);
  EXPECT_DOUBLE_EQ(m.velocity[1], -0.1);
  EXPECT_DOUBLE_EQ(m.velocity[2], 0.05);
  EXPECT_DOUBLE_EQ(m.velocity_covariance[0], 1e-4);
  EXPECT_DOUBLE_EQ(m.velocity_covariance[4], 1e-4);
  EXPECT_DOUBLE_EQ(m.velocity_covariance[8], 1e-4);
  EXPECT_DOUBLE_EQ(m.velocity_covariance[1], 0);
  EXPECT_EQ(m.beams_valid, 3);
}

TEST(DvlNode, LatencyClampsAtZero) {
  DvlParams p;
  p.latency_s = 0.5;
  DvlNode n(p);
  Capture c;
  n.attach(&c);
  n.feed(velocity_line(0.1, 0, 0, 0.004, 3.2, true, 0), 100'000);
  ASSERT_EQ(c.dvl.size(), 1u);
  EXPECT_EQ(c.dvl[0].utime, 0);
}

TEST(DvlNode, NoLockIsVelocityZeroAltitudeMinusOneAndCountsTransitions) {
  DvlNode n{DvlParams{}};
  Capture c;
  n.attach(&c);
  n.set_link(true, "", 0);
  n.feed(velocity_line(0.1, 0, 0, 0.004, 3.2, true, 0), 100'000);     // lock
  n.feed(velocity_line(0.5, 0.2, 0.1, 2.3, -1, false, 0), 200'000);   // lost
  n.feed(velocity_line(0.1, 0, 0, 0.004, 3.0, true, 1), 300'000);     // status 1: no lock
  n.feed(velocity_line(0.12, 0, 0, 0.004, 3.1, true, 0), 400'000);    // regained
  n.feed(velocity_line(0.0, 0, 0, 1.5, 45.25, false, 0), 1'000'000);  // lost again
  ASSERT_EQ(c.dvl.size(), 5u);
  for (int i : {1, 2, 4}) {
    SCOPED_TRACE(i);
    EXPECT_FALSE(c.dvl[i].bottom_lock);
    EXPECT_EQ(c.dvl[i].velocity[0], 0);
    EXPECT_EQ(c.dvl[i].velocity[1], 0);
    EXPECT_EQ(c.dvl[i].velocity[2], 0);
    EXPECT_EQ(c.dvl[i].altitude, -1);
    EXPECT_EQ(c.dvl[i].velocity_covariance[0], 0);
    EXPECT_EQ(checks::check(c.dvl[i]), nullptr);
  }
  EXPECT_EQ(c.dvl[2].status, 1);
  EXPECT_DOUBLE_EQ(c.dvl[1].fom, 2.3);
  EXPECT_TRUE(c.dvl[3].bottom_lock);
  EXPECT_EQ(n.counter_value("dvl.lock_lost"), 2);
  EXPECT_EQ(n.counter_value("dvl.lock_regained"), 1);
  EXPECT_EQ(status_at(n, c, 1'000'000), "no bottom lock (altitude 45.2 m, status 0)");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_DEGRADED);
  n.feed(velocity_line(0, 0, 0, 2.3, -1, false, 0), 1'500'000);
  EXPECT_EQ(status_at(n, c, 2'000'000), "no bottom lock (altitude none, status 0)");
}

TEST(DvlNode, MalformedInvalidIgnoredAndDeadReckoningAreCountedNotPublished) {
  DvlNode n{DvlParams{}};
  Capture c;
  n.attach(&c);
  n.set_link(true, "", 0);
  const std::vector<std::string> malformed = {"", "{\"vx\": 0.1, ", "garbage", "[1, 2]",
                                              "{\"vx\": 0.1}"};
  for (const auto& l : malformed) n.feed(l, 100'000);
  n.feed(R"({"type": "velocity", "vx": 0.1})", 100'000);          // no vy
  n.feed(velocity_line(25, 0, 0, 0.004, 3.2, true, 0), 100'000);  // |vx| > 20
  n.feed(R"({"type": "velocity", "vx": 0.1, "vy": 0, "vz": 0, "fom": 0.01, "altitude": 2,)"
         R"( "velocity_valid": true, "status": 0, "time": 1, "transducers": [{"beam_valid": 1}]})",
         100'000);  // a mistyped beam_valid
  n.feed(R"({"response_to": "get_config", "success": true, "type": "response"})", 100'000);
  n.feed(R"({"ts": 49056.8, "x": 12.4, "y": 64.1, "z": 1.7, "std": 0.31, "roll": 0.35,)"
         R"( "pitch": -1.64, "yaw": 149.28, "type": "position_local", "status": 0})",
         100'000);
  // Passes the parser but not the contract: fom 150 m/s (dvl_t's fom is [0, 100]).
  n.feed(velocity_line(0.1, 0, 0, 150, 3.2, true, 0), 100'000);
  EXPECT_TRUE(c.dvl.empty());
  EXPECT_EQ(n.counter_value("rejected.line.malformed"), 5);
  EXPECT_EQ(n.counter_value("rejected.line.invalid"), 3);
  EXPECT_EQ(n.counter_value("lines.ignored"), 1);
  EXPECT_EQ(n.counter_value("lines.dead_reckoning"), 1);
  EXPECT_EQ(n.counter_value("rejected.velocity.invalid"), 1);
  EXPECT_EQ(n.counter_value("lines.velocity"), 1);
  EXPECT_EQ(n.rejected(), 9);
  EXPECT_EQ(n.published(), 0);
}

TEST(DvlNode, FomAboveTheLimitIsPublishedCountedAndDegraded) {
  DvlParams p;
  p.max_fom = 0.05;
  DvlNode n(p);
  Capture c;
  n.attach(&c);
  n.set_link(true, "", 0);
  n.feed(velocity_line(0.1, 0, 0, 0.25, 3.2, true, 0), 900'000);
  ASSERT_EQ(c.dvl.size(), 1u);
  EXPECT_TRUE(c.dvl[0].bottom_lock);  // the DVL's word; tiller-nav applies its own limit
  EXPECT_EQ(n.counter_value("dvl.fom_high"), 1);
  EXPECT_EQ(status_at(n, c, 1'000'000),
            "bottom lock, altitude 3.2 m, fom 0.250 m/s (above max_fom 0.050 m/s)");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_DEGRADED);
}

TEST(DvlNode, TimeoutAndLinkFaults) {
  DvlParams p;
  p.timeout_s = 1.5;
  DvlNode n(p);
  Capture c;
  n.attach(&c);
  EXPECT_EQ(status_at(n, c, 0), "not connected to 192.168.194.95:16171: not connected yet");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_FAULT);
  n.set_link(true, "", 500'000);
  EXPECT_EQ(status_at(n, c, 1'000'000),
            "connected to 192.168.194.95:16171, no velocity report yet");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_EQ(status_at(n, c, 2'000'000),
            "no velocity report for 1.5 s (connected to 192.168.194.95:16171)");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_FAULT);
  n.feed(velocity_line(0.1, 0, 0, 0.004, 3.2, true, 0), 2'100'000);
  EXPECT_EQ(status_at(n, c, 3'000'000), "bottom lock, altitude 3.2 m, fom 0.004 m/s");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_OK);
  for (TimeUs t = 3'100'000; t < 4'000'000; t += 100'000) n.tick(t);
  EXPECT_EQ(status_at(n, c, 4'000'000),
            "no velocity report for 1.9 s (connected to 192.168.194.95:16171)");
  EXPECT_EQ(c.heartbeat.state, heartbeat_t::STATE_FAULT);
  n.set_link(false, "closed by the device", 4'050'000);
  EXPECT_EQ(status_at(n, c, 5'000'000),
            "not connected to 192.168.194.95:16171: closed by the device");
  n.set_link(false, "192.168.194.95:16171: Connection refused", 5'100'000);
  EXPECT_EQ(status_at(n, c, 6'000'000),
            "not connected to 192.168.194.95:16171: Connection refused");
  n.count_link(2, 1, 3);
  n.tick(7'000'000);
  EXPECT_EQ(n.counter_value("link.connects"), 2);
  EXPECT_EQ(n.counter_value("link.disconnects"), 1);
  EXPECT_EQ(n.counter_value("lines.overlong"), 3);
}

TEST(DvlNode, TheLoaderIsStrict) {
  const std::string root = TILLER_SOURCE_DIR;
  const DvlParams p = load_dvl_file(root + "/config/sensors/dvl_a50.yaml");
  EXPECT_EQ(p.host, "192.168.194.95");
  EXPECT_EQ(p.port, 16171);
  EXPECT_EQ(p.channel, "TILLER_DVL");
  EXPECT_EQ(p.yaw, 0);
  const auto error = [](const std::string& text) {
    try {
      load_dvl_params(config::Value::parse(text, "dvl.yaml"));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const DvlParams y =
      load_dvl_params(config::Value::parse("mounting: {yaw_deg: 90}\n", "dvl.yaml"));
  EXPECT_NEAR(y.yaw, M_PI / 2, 1e-12);
  EXPECT_NE(error("prot: 16171\n").find("dvl.yaml:1: prot: unknown key"), std::string::npos)
      << error("prot: 16171\n");
  EXPECT_NE(error("port: 70000\n").find("port"), std::string::npos);
  EXPECT_NE(error("port: x\n").find("dvl.yaml:1: port"), std::string::npos) << error("port: x\n");
  EXPECT_NE(error("mounting: 3\n").find("mounting"), std::string::npos) << error("mounting: 3\n");
  EXPECT_NE(error("mounting: {yaw: 90}\n").find("mounting.yaw: unknown key"), std::string::npos)
      << error("mounting: {yaw: 90}\n");
  EXPECT_NE(error("latency_s: -1\n").find("latency_s"), std::string::npos);
  EXPECT_NE(error("max_fom: 0\n").find("max_fom"), std::string::npos);
}

}  // namespace
}  // namespace tiller::sensors
