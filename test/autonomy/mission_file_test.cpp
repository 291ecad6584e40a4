// Mission files: YAML and CSV forms, the shipped missions, errors that name file and line.
#include <gtest/gtest.h>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/path_t.hpp>

#include <cstdio>
#include <fstream>
#include <string>

#include <sys/wait.h>

#include "core/angles.hpp"
#include "mission/geo.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::mission {
namespace {

std::string src(const std::string& rel) {
  return std::string(TILLER_SOURCE_DIR) + "/" + rel;
}

std::string write_tmp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(MissionFile, ShippedMissionsLoad) {
  for (const char* f : {"config/missions/default.yaml", "config/missions/vrx_wayfinding.yaml",
                        "config/missions/station_keeping.yaml", "config/missions/wayfinding.csv"}) {
    const auto m = load_mission_file(src(f));
    EXPECT_FALSE(m.waypoints.empty()) << f;
  }
  const auto d = load_mission_file(src("config/missions/default.yaml"));
  EXPECT_EQ(d.name, "default");
  EXPECT_LT(d.time_limit_s, 180);  // the main job's mission is short
  EXPECT_TRUE(d.waypoints.back().has_heading);
  EXPECT_NEAR(d.waypoints.back().heading, kPi, 1e-12);
}

TEST(MissionFile, YamlForms) {
  const auto p = write_tmp("m1.yaml",
                           "name: t\nis_translation: true\nwaypoints:\n  - [1, 2]\n"
                           "  - {north: 3, east: 4, heading_deg: -90}\n");
  const auto m = load_mission_file(p);
  ASSERT_EQ(m.waypoints.size(), 2u);
  EXPECT_TRUE(m.is_translation);
  EXPECT_DOUBLE_EQ(m.waypoints[0].east, 2);
  EXPECT_FALSE(m.waypoints[0].has_heading);
  EXPECT_NEAR(m.waypoints[1].heading, -kPi / 2, 1e-12);
  const auto path = to_path(m, 42, 7);
  EXPECT_EQ(path.n_waypoints, 2);
  EXPECT_EQ(path.path_id, 42);
  EXPECT_DOUBLE_EQ(path.waypoints[1].position[0], 3);
}

TEST(MissionFile, CsvForms) {
  const auto m = load_mission_file(src("config/missions/wayfinding.csv"));
  ASSERT_EQ(m.waypoints.size(), 3u);
  EXPECT_FALSE(m.waypoints[0].has_heading);
  EXPECT_TRUE(m.waypoints[2].has_heading);
  EXPECT_NEAR(m.waypoints[2].heading, kPi / 2, 1e-12);
  const auto y = write_tmp("m2.yaml", "waypoints_csv: m2.csv\n");
  write_tmp("m2.csv", "north,east\n1,1\n2,2\n");
  EXPECT_EQ(load_mission_file(y).waypoints.size(), 2u);
}

void expect_error(const std::string& path, const std::string& needle) {
  try {
    load_mission_file(path);
    FAIL() << "expected an error for " << path;
  } catch (const config::Error& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find(path), std::string::npos) << w;
    EXPECT_NE(w.find(needle), std::string::npos) << w;
  }
}

TEST(MissionFile, ErrorsNameFileLineAndWhat) {
  expect_error(write_tmp("b1.csv", "north,east\n1,1\n2,x\n"), ":3:");
  expect_error(write_tmp("b2.csv", "n,e\n1,1\n"), "header");
  expect_error(write_tmp("b3.csv", "north,east\n"), "at least one");
  expect_error(write_tmp("b4.yaml", "waypoints: []\n"), "waypoints");
  expect_error(write_tmp("b5.yaml", "waypoints:\n  - {north: 1, east: 2, heading: 3}\n"),
               "heading");
  expect_error(write_tmp("b6.yaml", "name: x\n"), "waypoints");
  expect_error(write_tmp("b7.yaml", "waypoints:\n  - [1, nan]\n"), "waypoints[0]");
}

TEST(MissionNode, PublishesPathThenModeAndArmRequest) {
  const auto m = load_mission_file(src("config/missions/default.yaml"));
  MissionNode node(m, 5, kUsPerSecond);
  LockstepExecutor ex(0);
  ex.add(node);
  std::vector<std::string> order;
  std::vector<arm_request_t> arms;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    order.push_back(ch);
    if (ch == channels::kArmRequest && arms.emplace_back().decode(d, 0, n) < 0) arms.pop_back();
  });
  // tiller-esc's arm state (its boot nonce) comes at 0.5 s: the arm request waits for it.
  arm_state_t st{};
  st.utime = 500'000;
  st.boot_nonce = 77;
  st.reason = "disarmed at start";
  ex.inject(channels::kArmState, st, 500'000);
  ex.run_until(1'500'000);
  ASSERT_GE(order.size(), 6u);
  EXPECT_EQ(order[0], channels::kPath);
  EXPECT_EQ(order[1], channels::kMode);
  EXPECT_NE(order[2], channels::kArmRequest);
  ASSERT_EQ(arms.size(), 1u);
  EXPECT_TRUE(arms[0].arm);
  EXPECT_EQ(arms[0].boot_nonce, 77);
  EXPECT_EQ(arms[0].utime, 500'000);
  EXPECT_EQ(node.sent(), 2);  // at 0 s and 1 s
}

// --datum-from-vehicle: the harbour plan publishes nothing until TILLER_DATUM, then flies in the
// vehicle's frame: with the datum 20 m south and 10 m west of the plan's home, every point is
// 20 m further north and 10 m further east than about home. A later, other datum is ignored and
// counted; a bad one is refused and counted. Without the flag the plan is about its home.
TEST(MissionNode, APlanInLatLonWaitsForTheVehiclesDatum) {
  const auto m = load_mission_file(src("config/missions/harbour.plan"));
  ASSERT_TRUE(m.geodetic());
  MissionNode node(m, 100, kUsPerSecond, false, {}, true);
  LockstepExecutor ex(0);
  ex.add(node);
  std::vector<path_t> paths;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch == channels::kPath && paths.emplace_back().decode(d, 0, n) < 0) paths.pop_back();
  });
  ex.run_until(2'000'000);
  EXPECT_TRUE(paths.empty());
  EXPECT_TRUE(node.waiting_for_datum());
  const LocalFrame home(*m.home);
  const GeoPoint south_west = home.to_geo(-20, -10);
  datum_t d{};
  d.utime = 2'100'000;
  d.latitude = 91;  // refused: nothing changes
  ex.inject(channels::kDatum, d, 2'100'000);
  d.latitude = south_west.lat_deg;
  d.longitude = south_west.lon_deg;
  d.altitude = m.home->alt_m;
  d.source = datum_t::SOURCE_FIRST_FIX;
  ex.inject(channels::kDatum, d, 2'200'000);
  ex.run_until(2'500'000);
  EXPECT_FALSE(node.waiting_for_datum());
  EXPECT_EQ(node.counter_value("rejected.datum.invalid"), 1);
  ASSERT_FALSE(paths.empty());
  // Leg 1 from home (no odometry: the start is home), through (30, 0) and (30, 25) to the loiter.
  const auto& w = paths.front().waypoints;
  ASSERT_EQ(w.size(), 4u);
  EXPECT_NEAR(w[0].position[0], 20.0, 0.01);  // home, now 20 m north of the datum
  EXPECT_NEAR(w[0].position[1], 10.0, 0.01);
  EXPECT_NEAR(w[1].position[0], 50.0, 0.01);
  EXPECT_NEAR(w[1].position[1], 10.0, 0.01);
  EXPECT_NEAR(w[3].position[0], 30.0, 0.01);
  EXPECT_NEAR(w[3].position[1], 35.0, 0.01);
  d.latitude += 0.001;
  ex.inject(channels::kDatum, d, 3'000'000);
  ex.run_until(3'500'000);
  EXPECT_EQ(node.counter_value("datum.later_ignored"), 1);
  EXPECT_NEAR(paths.back().waypoints[1].position[0], 50.0, 0.01);
}

// tiller-mission's command line: a bad --repeat-s / --path-id names the flag and what was
// expected, and --config (in every tool's help) is refused rather than ignored. All of these
// exit before any LCM is opened.
TEST(MissionTool, BadFlagsNameTheFlagAndTheExpectedValue) {
  const std::pair<const char*, const char*> cases[] = {
      {"--repeat-s abc",
       "--repeat-s: expected a number of seconds >= 0 (0 = publish once), got 'abc'"},
      {"--repeat-s -1",
       "--repeat-s: expected a number of seconds >= 0 (0 = publish once), got '-1'"},
      {"--repeat-s 1s",
       "--repeat-s: expected a number of seconds >= 0 (0 = publish once), got '1s'"},
      {"--path-id 12x", "--path-id: expected a whole number >= 0 (int64), got '12x'"},
      {"--path-id 99999999999999999999",
       "--path-id: expected a whole number >= 0 (int64), got '99999999999999999999'"},
      {"--start-std-m x", "--start-std-m: expected a number of metres in [0.001, 1000], got 'x'"},
      {"--start-settle-s -1",
       "--start-settle-s: expected a number of seconds in [0, 3600], got '-1'"},
      {"--config config/missions/default.yaml",
       "--config is not taken: tiller-mission has no config file"},
  };
  for (const auto& [flags, message] : cases) {
    SCOPED_TRACE(flags);
    const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-mission " + flags + " 2>&1";
    FILE* f = popen(cmd.c_str(), "r");
    ASSERT_NE(f, nullptr);
    std::string out;
    char buf[256];
    while (fgets(buf, sizeof buf, f)) out += buf;
    const int status = pclose(f);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << out;
    EXPECT_NE(out.find(message), std::string::npos) << out;
    EXPECT_EQ(out.find("stod"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace tiller::mission
