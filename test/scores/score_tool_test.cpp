// tiller-score on synthetic logs: a one-point path is scored as the follower follows it (from
// where the boat was, so the cross-track is the distance to that line, not to the goal), the
// wayfinding mean leaves out the start, a run that never completes says so, and a run on
// estimated state is scored on the estimate too.
#include <gtest/gtest.h>

#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "runtime/log.hpp"

namespace tiller {
namespace {

template <class Msg>
void put(LogWriter& w, const std::string& ch, const Msg& m, TimeUs t) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  w.write(ch, buf.data(), static_cast<int>(buf.size()), t);
}

// A boat that starts at (0, 2) and drives straight north toward the one waypoint (10, 2) at
// 1 m/s for 12 s; if `complete` it gets there (the follower says complete at t = 10 s), else
// it stops halfway.
std::string write_log(const std::string& name, bool complete, double estimate_east = -1) {
  const std::string path = std::string(::testing::TempDir()) + name;
  LogWriter w(path);
  path_t p{};
  p.path_id = 3;
  p.n_waypoints = 1;
  p.waypoints.resize(1);
  p.waypoints[0].position[0] = 10;
  p.waypoints[0].position[1] = 2;
  put(w, "TILLER_PATH", p, 0);
  for (int k = 0; k <= 120; ++k) {
    const TimeUs t = k * 100'000;
    odometry_t o{};
    o.utime = t;
    o.position[0] = std::min(complete ? 10.0 : 5.0, 0.1 * k);
    o.position[1] = 2;
    put(w, "TILLER_GROUND_TRUTH", o, t + 1);
    if (estimate_east >= 0) {  // tiller-nav's estimate, beside the line
      o.position[1] = estimate_east;
      put(w, "TILLER_ODOMETRY", o, t + 1);
    }
    path_progress_t pr{};
    pr.utime = t;
    pr.path_id = 3;
    pr.segment = 0;
    pr.n_waypoints = 2;
    pr.complete = complete && k >= 100;
    put(w, "TILLER_PATH_PROGRESS", pr, t + 2);
  }
  return path;
}

std::string run_score(const std::string& log) {
  const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-score --log " + log;
  FILE* f = popen(cmd.c_str(), "r");
  EXPECT_NE(f, nullptr);
  std::string out;
  char buf[256];
  while (f && fgets(buf, sizeof buf, f)) out += buf;
  if (f) {
    EXPECT_EQ(pclose(f), 0) << out;
  }
  return out;
}

TEST(ScoreTool, OnePointPathIsScoredFromWhereTheBoatWas) {
  const auto out = run_score(write_log("one_point.lcmlog", true));
  // On the line from the start (0, 2) to the goal: no cross-track (the distance to the goal
  // would have given an RMS of about 5.8 m and a max of 10 m).
  EXPECT_NE(out.find("cross-track RMS     0.000 m (max 0.000 m)"), std::string::npos) << out;
  EXPECT_NE(out.find("waypoints           2 (reached in order 2, missed 0)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("time to complete    10.0 s"), std::string::npos) << out;
  // Wayfinding: the start is not a waypoint of the task; the goal was reached exactly.
  EXPECT_NE(out.find("VRX wayfinding      0.000 (mean over 1 waypoints, the start point left out)"),
            std::string::npos)
      << out;
}

// On estimated state (an odometry 0.3 m east of the truth all along): the path is scored on
// the truth and again on the estimate, each from where it was. The truth runs on its line; the
// estimate's line runs from (0, 2.3) to the goal (10, 2), and the estimate, going straight north,
// is 0.3 n / sqrt(100.09) m off it at north n: RMS over n = 0, 0.1, ..., 10 of
// 0.3 sqrt(33.5 / 100.09) = 0.174 m, max 0.29987 m at the end.
TEST(ScoreTool, OnEstimatedStateTheEstimateIsScoredToo) {
  const auto out = run_score(write_log("estimated.lcmlog", true, 2.3));
  EXPECT_NE(out.find("estimation error    position RMS 0.300 m (max 0.300 m)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("samples); from the mission's start 0.300 m, 0.00 deg"), std::string::npos)
      << out;
  EXPECT_NE(out.find("cross-track RMS     0.000 m (max 0.000 m)"), std::string::npos) << out;
  EXPECT_NE(out.find("on the estimate     cross-track RMS 0.174 m (max 0.300 m), waypoints "
                     "reached 2, missed 0, time to complete 10.0 s (TILLER_ODOMETRY, 121 "
                     "samples)"),
            std::string::npos)
      << out;
  // On the truth alone neither line.
  const auto truth = run_score(write_log("truth_only.lcmlog", true));
  EXPECT_EQ(truth.find("on the estimate"), std::string::npos) << truth;
  EXPECT_EQ(truth.find("estimation error"), std::string::npos) << truth;
}

TEST(ScoreTool, NotCompletedSaysSo) {
  const auto out = run_score(write_log("not_completed.lcmlog", false));
  EXPECT_NE(out.find("time to complete    not completed"), std::string::npos) << out;
  EXPECT_EQ(out.find("-1.0 s"), std::string::npos) << out;
  EXPECT_EQ(out.find("VRX station keeping"), std::string::npos) << out;  // nothing to score
}

}  // namespace
}  // namespace tiller
