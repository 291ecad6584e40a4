// score_events on a hand-made run on estimated state: the path scored on the truth, the
// estimation error, and the path scored on the estimate (the pose the follower followed), each
// against numbers computed by hand.
#include <gtest/gtest.h>

#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scores/log_scores.hpp"

namespace tiller::scores {
namespace {

// A state at `utime` (the instant it is of; the estimation error compares states there).
odometry_t pose(double north, double east, TimeUs utime) {
  odometry_t o{};
  o.utime = utime;
  o.position[0] = north;
  o.position[1] = east;
  return o;
}

// TILLER_PATH at t = 0, path_id `id`: (0, 0) -> (north, 0) with 2 points, the goal (north, 0)
// alone with 1.
Event path_event(double north, int points, std::int64_t id) {
  path_t p{};
  p.path_id = id;
  p.n_waypoints = points;
  p.waypoints.resize(points);
  p.waypoints[points - 1].position[0] = north;
  return encode("TILLER_PATH", 0, p);
}

// Path (0, 0) -> (10, 0), given at t = 0. At t = k s (k = 0..10) the truth is at (k, 0.5), the
// last one at (10, 1.3); the estimate at (k, 0.1). With `complete` the follower says complete
// at t = 10 s.
std::vector<Event> run_on_estimate(bool complete) {
  std::vector<Event> ev;
  ev.push_back(path_event(10, 2, 7));
  for (int k = 0; k <= 10; ++k) {
    const TimeUs t = k * kUsPerSecond;
    ev.push_back(encode("TILLER_GROUND_TRUTH", t, pose(k, k < 10 ? 0.5 : 1.3, t)));
    ev.push_back(encode("TILLER_ODOMETRY", t, pose(k, 0.1, t)));
    if (complete && k == 10) {
      path_progress_t pr{};
      pr.path_id = 7;
      pr.complete = true;
      ev.push_back(encode("TILLER_PATH_PROGRESS", t, pr));
    }
  }
  return ev;
}

TEST(LogScores, ThePathIsScoredOnTheTruthAndOnTheEstimate) {
  const auto r = score_events(run_on_estimate(true));
  EXPECT_EQ(r.pose_channel, "TILLER_GROUND_TRUTH");
  ASSERT_TRUE(r.estimated());
  // Truth: 0.5 m off the line ten times, 1.3 m from the goal at the end: the goal is missed
  // (1.3 m > the 1 m visit radius; (9, 0.5) is 1.118 m from it).
  const auto& t = r.path_scores;
  EXPECT_NEAR(t.cross_track_rms, std::sqrt((10 * 0.25 + 1.69) / 11), 1e-12);
  EXPECT_DOUBLE_EQ(t.cross_track_max, 1.3);
  EXPECT_EQ(t.waypoints_reached, 1);
  EXPECT_EQ(t.waypoints_missed, 1);
  EXPECT_DOUBLE_EQ(t.time_to_complete, 10.0);  // the follower's completion
  // Estimation error: 0.4 m ten times, 1.2 m at the end; heading 0 on both.
  EXPECT_EQ(r.estimation_samples, 11u);
  EXPECT_NEAR(r.position_error_rms, std::sqrt((10 * 0.16 + 1.44) / 11), 1e-12);
  EXPECT_NEAR(r.position_error_max, 1.2, 1e-12);
  EXPECT_DOUBLE_EQ(r.heading_error_rms, 0.0);
  // On the estimate: 0.1 m off the line throughout, both waypoints reached (the goal at t = 10).
  ASSERT_TRUE(r.estimate_path_scores.has_value());
  const auto& e = *r.estimate_path_scores;
  EXPECT_EQ(r.estimate_poses.size(), 11u);
  EXPECT_NEAR(e.cross_track_rms, 0.1, 1e-12);
  EXPECT_NEAR(e.cross_track_max, 0.1, 1e-12);
  EXPECT_EQ(e.waypoints_reached, 2);
  EXPECT_EQ(e.waypoints_missed, 0);
  EXPECT_DOUBLE_EQ(e.time_to_complete, 10.0);
  EXPECT_NEAR(e.final_position_error, 0.1, 1e-12);
  // The true cross-track is at most the estimate's plus the estimation error, sample by sample.
  EXPECT_LE(t.cross_track_max, e.cross_track_max + r.position_error_max + 1e-12);
}

// The estimation error from the mission's start: a filter converging from a 3 m first fix before
// the mission (t < 2 s) counts in the whole run's figure only. Hand-computed: errors 3, 1, 0.2,
// 0.2, 0.2 m and heading 0.1 rad at t = 0, 1 only.
TEST(LogScores, TheEstimationErrorFromTheMissionsStart) {
  std::vector<Pose> truth, estimate;
  const double err[] = {3, 1, 0.2, 0.2, 0.2};
  for (int k = 0; k < 5; ++k) {
    truth.push_back({double(k), 1.0 * k, 0, 0});
    estimate.push_back({double(k), 1.0 * k, err[k], k < 2 ? 0.1 : 0.0});
  }
  RunScores r;
  score_estimation(estimate, truth, r, 2.0);
  EXPECT_EQ(r.estimation_samples, 5u);
  EXPECT_NEAR(r.position_error_rms, std::sqrt((9 + 1 + 3 * 0.04) / 5), 1e-12);
  EXPECT_NEAR(r.heading_error_rms, std::sqrt(2 * 0.01 / 5), 1e-12);
  EXPECT_NEAR(r.mission_position_error_rms, 0.2, 1e-12);
  EXPECT_NEAR(r.mission_heading_error_rms, 0.0, 1e-12);
  // From 0: the same as the whole run.
  score_estimation(estimate, truth, r, 0.0);
  EXPECT_NEAR(r.mission_position_error_rms, r.position_error_rms, 1e-12);
}

TEST(LogScores, WithoutACompletionEachPoseCompletesWhenItReachesTheGoal) {
  const auto r = score_events(run_on_estimate(false));
  EXPECT_DOUBLE_EQ(r.path_scores.time_to_complete, -1.0);  // the truth never got within 1 m
  ASSERT_TRUE(r.estimate_path_scores.has_value());
  EXPECT_DOUBLE_EQ(r.estimate_path_scores->time_to_complete, 10.0);  // (10, 0.1) at t = 10
  // Both scored to the end of the run: the same cross-track as above.
  EXPECT_NEAR(r.estimate_path_scores->cross_track_rms, 0.1, 1e-12);
}

// A one-point path is followed from where the follower thought the boat was: the estimate's
// line starts at the estimate's first pose, the truth's at the truth's. Both start 0.4 m off
// the goal's line of north, on either side, and go straight to the goal (10, 0).
TEST(LogScores, AOnePointPathStartsWhereEachPoseWas) {
  std::vector<Event> ev;
  ev.push_back(path_event(10, 1, 1));
  for (int k = 0; k <= 10; ++k) {
    const TimeUs t = k * kUsPerSecond;
    ev.push_back(encode("TILLER_GROUND_TRUTH", t, pose(k, 0.4 * (10 - k) / 10, t)));
    ev.push_back(encode("TILLER_ODOMETRY", t, pose(k, -0.4 * (10 - k) / 10, t)));
  }
  const auto r = score_events(ev);
  ASSERT_EQ(r.path.size(), 2u);
  EXPECT_DOUBLE_EQ(r.path[0].east, 0.4);
  ASSERT_EQ(r.estimate_path.size(), 2u);
  EXPECT_DOUBLE_EQ(r.estimate_path[0].east, -0.4);
  // Each runs straight from its start to the goal: on its own line (from the truth's start the
  // estimate would be 0.8 m off at t = 0).
  EXPECT_NEAR(r.estimate_path_scores->cross_track_max, 0.0, 1e-12);
  EXPECT_NEAR(r.path_scores.cross_track_max, 0.0, 1e-12);
}

// On truth odometry the simulator publishes the truth as TILLER_ODOMETRY too: no estimate, and
// no estimation lines, though the interpolation between truth samples may leave a rounding
// error (tiller-run's truth runs: 4e-19 m at most).
TEST(LogScores, TruthOdometryIsNoEstimate) {
  std::vector<Event> ev;
  ev.push_back(path_event(1, 2, 0));
  for (int k = 0; k <= 10; ++k) {
    ev.push_back(encode("TILLER_GROUND_TRUTH", k * 100'000, pose(0.1 * k, 0.2, k * 100'000)));
    if (k < 10)
      ev.push_back(encode("TILLER_ODOMETRY", k * 100'000 + 30'000,
                          pose(0.1 * k + 0.03, 0.2, k * 100'000 + 30'000)));
  }
  const auto r = score_events(ev);
  EXPECT_EQ(r.estimation_samples, 10u);
  EXPECT_LT(r.position_error_max, 1e-12);
  EXPECT_FALSE(r.estimated());
  ASSERT_TRUE(r.estimate_path_scores.has_value());
  EXPECT_DOUBLE_EQ(r.estimate_path_scores->cross_track_rms, r.path_scores.cross_track_rms);
  char buf[4096] = {};
  std::FILE* f = fmemopen(buf, sizeof buf - 1, "w");
  print_scores(r, f);
  std::fclose(f);
  EXPECT_EQ(std::string(buf).find("on the estimate"), std::string::npos) << buf;
  EXPECT_EQ(std::string(buf).find("estimation error"), std::string::npos) << buf;
}

// A live log: the simulator publishes the same state (same utime) on both channels, and the
// logger receives TILLER_ODOMETRY up to 0.9 ms after TILLER_GROUND_TRUTH. The states are
// compared at their own time: no estimate. (Compared at the receive times, the truth moving at
// 1.5 m/s gave a 1.35 mm "estimation error" and the estimation lines, which broke a test's awk.)
TEST(LogScores, TruthOdometryReceivedLaterIsNoEstimate) {
  std::vector<Event> ev;
  ev.push_back(path_event(10, 2, 0));
  for (int k = 0; k <= 100; ++k) {
    const TimeUs t = k * 50'000;
    const odometry_t o = pose(1.5 * to_seconds(t), 0.2, t);
    ev.push_back(encode("TILLER_GROUND_TRUTH", t + 100, o));
    ev.push_back(encode("TILLER_ODOMETRY", t + 100 + 9 * (k % 100), o));
  }
  const auto r = score_events(ev);
  EXPECT_EQ(r.estimation_samples, 101u);
  EXPECT_EQ(r.position_error_max, 0.0);
  EXPECT_FALSE(r.estimated());
}

TEST(LogScores, TheEstimateLineIsPrinted) {
  const auto r = score_events(run_on_estimate(true));
  char buf[4096] = {};
  std::FILE* f = fmemopen(buf, sizeof buf - 1, "w");
  print_scores(r, f);
  std::fclose(f);
  const std::string out = buf;
  EXPECT_NE(out.find("on the estimate     cross-track RMS 0.100 m (max 0.100 m), waypoints "
                     "reached 2, missed 0, time to complete 10.0 s (TILLER_ODOMETRY, 11 samples)"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("waypoints           2 (reached in order 1, missed 1)"), std::string::npos)
      << out;
}

}  // namespace
}  // namespace tiller::scores
