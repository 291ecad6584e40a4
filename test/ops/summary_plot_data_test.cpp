// tiller-log summary flags what needs attention: a process that missed more than 1 % of its
// ticks (2 % is flagged, 0.5 % is not), a DEGRADED or FAULT heartbeat at any time, rejected
// messages, real time refused (realtime.refused = 1); and it explains its columns. tiller-plot's
// data: the heading is unwrapped (a turn through south continues past 180 instead of jumping to
// -180), and each waypoint reached and the mission's completion are marked where and when the path
// follower said so; a waypoint the follower switched past without the trajectory coming within
// 1 m of it is drawn as missed, with its closest approach.
#include <gtest/gtest.h>
#include <unistd.h>

#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/angles.hpp"
#include "logtools/logsummary.hpp"
#include "logtools/plotdata.hpp"
#include "runtime/channels.hpp"

namespace tiller::logtools {
namespace {

// One heartbeat a second for 10 s from a process ticking at 50 Hz that missed `missed` of its
// 500 grid points by the end; `state` from 3 s to 5 s.
std::vector<Event> esc_heartbeats(std::int64_t missed, std::int8_t state = 0) {
  std::vector<Event> log;
  for (int s = 1; s <= 10; ++s) {
    heartbeat_t hb{};
    hb.process = "esc";
    hb.state = s >= 3 && s <= 5 ? state : heartbeat_t::STATE_OK;
    hb.status = hb.state ? "degraded: ESC 2 missing" : "ok";
    hb.n_counters = 2;
    hb.counter_names = {"ticks.run", "ticks.missed"};
    const std::int64_t m = missed * s / 10;
    hb.counter_values = {50 * s - m, m};
    log.push_back(encode("TILLER_HEARTBEAT_ESC", s * kUsPerSecond, hb));
  }
  return log;
}

TEST(LogSummaryAttention, MissedTicksAboveOnePercentAreFlagged) {
  const LogSummary two = summarize(esc_heartbeats(10));  // 10 of 500: 2 %
  ASSERT_EQ(two.processes.size(), 1u);
  EXPECT_EQ(two.processes[0].ticks_run, 490);
  EXPECT_EQ(two.processes[0].ticks_missed, 10);
  EXPECT_DOUBLE_EQ(two.processes[0].missed_fraction(), 0.02);
  ASSERT_EQ(two.attention.size(), 1u);
  EXPECT_EQ(two.attention[0], "esc: missed 10 of 500 ticks (2.0 %, above 1 %)");
  const std::string text = format_summary(two);
  EXPECT_NE(text.find("ATTENTION: esc: missed 10 of 500 ticks (2.0 %, above 1 %)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("columns: count = messages"), std::string::npos);
  EXPECT_NE(text.find("missed = ticks.missed / (ticks.run + ticks.missed)"), std::string::npos);
  EXPECT_EQ(text.find("ticks.run ="), std::string::npos);  // a column, not a counter line

  const LogSummary few = summarize(esc_heartbeats(2));  // 2 of 500: 0.4 %
  EXPECT_NEAR(few.processes[0].missed_fraction(), 0.004, 1e-12);
  EXPECT_TRUE(few.attention.empty());
  EXPECT_NE(format_summary(few).find("attention: nothing"), std::string::npos);
}

TEST(LogSummaryAttention, HalfAPercentIsNotFlagged) {
  std::vector<Event> log = esc_heartbeats(0);
  // 0.5 %: 5 of 1000 (a 100 Hz process).
  heartbeat_t hb{};
  hb.process = "mixer";
  hb.n_counters = 2;
  hb.counter_names = {"ticks.run", "ticks.missed"};
  hb.counter_values = {995, 5};
  log.push_back(encode("TILLER_HEARTBEAT_MIXER", 10 * kUsPerSecond, hb));
  const LogSummary s = summarize(log);
  ASSERT_EQ(s.processes.size(), 2u);
  EXPECT_DOUBLE_EQ(s.processes[1].missed_fraction(), 0.005);
  EXPECT_TRUE(s.attention.empty()) << s.attention[0];
}

TEST(LogSummaryAttention, DegradedAtAnyTimeAndRejectionsAreFlagged) {
  std::vector<Event> log = esc_heartbeats(0, heartbeat_t::STATE_DEGRADED);
  heartbeat_t hb{};
  hb.process = "mixer";
  hb.rejected = 3;
  hb.n_counters = 1;
  hb.counter_names = {"rejected.wrench.nan"};
  hb.counter_values = {3};
  log.push_back(encode("TILLER_HEARTBEAT_MIXER", 10 * kUsPerSecond, hb));
  const LogSummary s = summarize(log);
  ASSERT_EQ(s.attention.size(), 2u);
  // The log starts at the first heartbeat (1 s); DEGRADED from 3 s is 2.0 s in.
  EXPECT_EQ(s.attention[0],
            "esc: DEGRADED from 2.0 s (\"degraded: ESC 2 missing\"), ok again by its last "
            "heartbeat");
  EXPECT_EQ(s.attention[1], "mixer: rejected 3, stale 0 (rejected.wrench.nan = 3)");
  EXPECT_EQ(s.processes[0].worst_state, heartbeat_t::STATE_DEGRADED);
  EXPECT_EQ(s.processes[0].state, heartbeat_t::STATE_OK);
}

TEST(PlotData, HeadingIsUnwrapped) {
  EXPECT_DOUBLE_EQ(unwrap_deg(170.0, deg_to_rad(-170.0)), 190.0);
  EXPECT_DOUBLE_EQ(unwrap_deg(-175.0, deg_to_rad(175.0)), -185.0);
  EXPECT_NEAR(unwrap_deg(725.0, deg_to_rad(10.0)), 730.0, 1e-9);
  EXPECT_NEAR(unwrap_deg(0.0, deg_to_rad(90.0)), 90.0, 1e-12);
}

TEST(PlotData, UnwrappedHeadingAndWaypointMarksFromALog) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tiller-plotdata-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::vector<Event> log;
  // A full turn to starboard at 30 deg/s sampled every second: 0, 30, ..., 360 (wrapped in the
  // message, so 180 and beyond arrive as -180 ... 0).
  for (int k = 0; k <= 12; ++k) {
    odometry_t o{};
    o.position[0] = k;
    o.orientation[2] = wrap_pi(deg_to_rad(30.0 * k));
    log.push_back(encode(channels::kGroundTruth, k * kUsPerSecond, o));
    path_progress_t p{};
    p.path_id = 7;
    p.n_waypoints = 4;
    p.segment = k < 4 ? 0 : k < 6 ? 1 : 2;  // waypoint 1 at 4 s, waypoint 2 at 6 s
    p.complete = k >= 10;                   // complete at 10 s
    log.push_back(encode(channels::kPathProgress, k * kUsPerSecond + 1, p));
  }
  const PlotData pd = write_plot_data(log, dir.string());
  std::ifstream traj(dir / "traj.csv");
  std::string line;
  std::getline(traj, line);
  std::vector<double> heading;
  while (std::getline(traj, line)) {
    std::stringstream ss(line);
    std::string cell;
    for (int c = 0; c < 4; ++c) std::getline(ss, cell, ',');
    heading.push_back(std::stod(cell));
  }
  ASSERT_EQ(heading.size(), 13u);
  for (int k = 0; k <= 12; ++k) EXPECT_NEAR(heading[k], 30.0 * k, 1e-4) << k;
  ASSERT_EQ(pd.marks.size(), 3u);
  EXPECT_NEAR(pd.marks[0].t, 4.0 + 1e-6, 1e-9);
  EXPECT_EQ(pd.marks[0].waypoint, 1);
  EXPECT_FALSE(pd.marks[0].complete);
  EXPECT_DOUBLE_EQ(pd.marks[0].north, 4.0);  // where the vehicle was
  EXPECT_EQ(pd.marks[1].waypoint, 2);
  EXPECT_NEAR(pd.marks[1].t, 6.0 + 1e-6, 1e-9);
  EXPECT_TRUE(pd.marks[2].complete);
  EXPECT_EQ(pd.marks[2].waypoint, 3);
  EXPECT_DOUBLE_EQ(pd.marks[2].north, 10.0);
  std::ifstream reached(dir / "reached.csv");
  std::getline(reached, line);
  std::getline(reached, line);
  EXPECT_EQ(line, "4,4,0,1");
  fs::remove_all(dir);
}

// The path (0,0) -> (4,0) -> (6,5) -> (10,0); the boat goes straight north along east = 0 at
// 1 m/s, and the follower switches past waypoint 1 at 4 s and waypoint 2 at 6 s. Waypoint 1 is
// on the track (reached); waypoint 2 is 5 m east of it, the closest approach from the previous
// switch (4 s) to the completion (10 s) is at (6, 0): missed by 5.000 m. Before the fix the plot
// drew it as reached (a mark for every switch).
TEST(PlotData, AWaypointPassedOutsideTheRadiusIsMarkedMissed) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tiller-plotmiss-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::vector<Event> log;
  path_t path{};
  path.path_id = 7;
  for (const auto& [n, e] : {std::pair{0.0, 0.0}, {4.0, 0.0}, {6.0, 5.0}, {10.0, 0.0}}) {
    waypoint_t w{};
    w.position[0] = n;
    w.position[1] = e;
    path.waypoints.push_back(w);
  }
  path.n_waypoints = 4;
  log.push_back(encode(channels::kPath, 0, path));
  for (int k = 0; k <= 12; ++k) {
    odometry_t o{};
    o.position[0] = k;
    log.push_back(encode(channels::kGroundTruth, k * kUsPerSecond + 2, o));
    path_progress_t p{};
    p.path_id = 7;
    p.n_waypoints = 4;
    p.segment = k < 4 ? 0 : k < 6 ? 1 : 2;
    p.complete = k >= 10;
    log.push_back(encode(channels::kPathProgress, k * kUsPerSecond + 3, p));
  }
  const PlotData pd = write_plot_data(log, dir.string());
  ASSERT_EQ(pd.marks.size(), 3u);
  EXPECT_FALSE(pd.marks[0].missed);
  EXPECT_NEAR(pd.marks[0].closest, 0.0, 1e-12);
  EXPECT_TRUE(pd.marks[1].missed);
  EXPECT_NEAR(pd.marks[1].closest, 5.0, 1e-12);
  EXPECT_TRUE(pd.marks[2].complete);
  std::string line;
  std::ifstream missed(dir / "missed.csv");
  std::getline(missed, line);
  std::getline(missed, line);
  EXPECT_EQ(line, "6,6,0,2,5");
  std::ifstream reached(dir / "reached.csv");
  std::getline(reached, line);
  std::getline(reached, line);
  EXPECT_EQ(line, "4,4,0,1");
  EXPECT_FALSE(std::getline(reached, line));  // waypoint 2 is not among the reached
  const std::string script = gnuplot_script(pd, dir.string(), "x.png", "t");
  EXPECT_NE(script.find("waypoint MISSED"), std::string::npos);
  EXPECT_NE(script.find("'2 missed'"), std::string::npos);
  fs::remove_all(dir);
}

TEST(LogSummaryAttention, RefusedRealTimeIsFlagged) {
  std::vector<Event> log = esc_heartbeats(0);
  heartbeat_t hb{};
  hb.process = "mixer";
  hb.n_counters = 3;
  hb.counter_names = {"realtime.locked", "realtime.priority", "realtime.refused"};
  hb.counter_values = {0, 0, 1};
  log.push_back(encode("TILLER_HEARTBEAT_MIXER", 10 * kUsPerSecond, hb));
  hb.process = "granted";
  hb.counter_values = {1, 40, 0};
  log.push_back(encode("TILLER_HEARTBEAT_GRANTED", 10 * kUsPerSecond, hb));
  const LogSummary s = summarize(log);
  ASSERT_EQ(s.attention.size(), 1u);
  EXPECT_EQ(s.attention[0],
            "mixer: real time asked for and refused (realtime.refused = 1): it ran on the normal "
            "scheduler; its first output lines say what is missing (docs/operations.md, \"Real "
            "time\")");
}

}  // namespace
}  // namespace tiller::logtools
