// Scores: hand-computed cross-track, completion, final errors and the VRX formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "scores/path_metrics.hpp"
#include "scores/scores.hpp"

namespace tiller::scores {
namespace {

constexpr double kPiForTest = 3.14159265358979323846;

TEST(Scores, VrxError) {
  EXPECT_DOUBLE_EQ(vrx_error(0, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(vrx_error(2, 1.0), 2 + 0.5625);
  EXPECT_DOUBLE_EQ(vrx_error(1, 0), 1);
}

TEST(Scores, DistanceToPath) {
  const std::vector<Goal> p{{0, 0}, {10, 0}, {10, 10}};
  EXPECT_DOUBLE_EQ(distance_to_path(5, 2, p), 2);
  EXPECT_DOUBLE_EQ(distance_to_path(12, 5, p), 2);
  EXPECT_DOUBLE_EQ(distance_to_path(-3, -4, p), 5);  // beyond the first point
  EXPECT_DOUBLE_EQ(distance_to_path(3, 4, {{0, 0}}), 5);
}

TEST(Scores, PathScoresByHand) {
  Goal g{10, 0, true, 0.0};
  const std::vector<Goal> path{{0, 0}, g};
  // 1 m off the path, then on it, then at the goal with a 0.2 rad heading error.
  const std::vector<Pose> run{{0, 0, 1, 0}, {1, 5, 0, 0}, {2, 9.5, 0, 0.2}, {3, 10, 0, 0.2}};
  const auto s = score_path(run, path, 0.0, 2.0, 1.5);          // visit radius 1.5 m
  EXPECT_NEAR(s.cross_track_rms, std::sqrt(1.0 / 3.0), 1e-12);  // samples at t = 0, 1, 2
  EXPECT_DOUBLE_EQ(s.cross_track_max, 1.0);
  EXPECT_DOUBLE_EQ(s.time_to_complete, 2.0);
  EXPECT_EQ(s.waypoints_reached, 2);
  EXPECT_EQ(s.waypoints_missed, 0);
  EXPECT_DOUBLE_EQ(s.final_position_error, 0.0);
  EXPECT_NEAR(s.final_heading_error, 0.2, 1e-12);
  // Wayfinding: the first point is where the boat started (1 m < the 1.5 m visit radius): not
  // a waypoint of the task, left out; the goal's best E = 0 + 0.2.
  EXPECT_TRUE(s.start_excluded);
  EXPECT_EQ(s.wayfinding_points, 1);
  EXPECT_NEAR(s.vrx_wayfinding, 0.2, 1e-12);
  // Without the follower's completion time: the time the last point was reached in order.
  EXPECT_DOUBLE_EQ(score_path(run, path, 0.0, std::nullopt, 1.5).time_to_complete, 2.0);
}

// VRX scores the task's waypoints (docs/autonomy.md, scores): a first point the boat does not start
// at is one of them and is scored; one it starts at is not.
TEST(Scores, WayfindingLeavesOutTheStartOnly) {
  const std::vector<Goal> path{{0, 0}, {10, 0}};
  // Starts 3 m from the first point: every point scored. Best E: 1 (t = 1), 0 (t = 2).
  const std::vector<Pose> far{{0, -3, 0, 0}, {1, -1, 0, 0}, {2, 10, 0, 0}};
  auto s = score_path(far, path, 0.0);
  EXPECT_FALSE(s.start_excluded);
  EXPECT_EQ(s.wayfinding_points, 2);
  EXPECT_NEAR(s.vrx_wayfinding, 0.5, 1e-12);
  // Starts at it (within the 1 m visit radius, at the time the path was given): left out.
  const std::vector<Pose> at{{0, -3, 0, 0}, {1, 0.2, 0, 0}, {2, 9, 0, 0}};
  s = score_path(at, path, 1.0);
  EXPECT_TRUE(s.start_excluded);
  EXPECT_EQ(s.wayfinding_points, 1);
  EXPECT_NEAR(s.vrx_wayfinding, 1.0, 1e-12);
  // A closed course: the start and the goal are the same place; the goal is still scored.
  const std::vector<Goal> box{{0, 0}, {10, 0}, {0, 0, true, kPiForTest}};
  const std::vector<Pose> run{{0, 0, 0, 0}, {1, 10, 0, 0}, {2, 0, 0, 0}};
  s = score_path(run, box, 0.0);
  EXPECT_TRUE(s.start_excluded);
  EXPECT_EQ(s.wayfinding_points, 2);
  EXPECT_NEAR(s.vrx_wayfinding, (0 + kPiForTest) / 2, 1e-12);  // the goal: facing north, not south
}

// A vehicle that begins away from the first point, beside or past it along the first segment (it
// drifted while the mission waited for the estimate), joins the first segment where it is, as the
// follower does: the first point counts as reached and is not a wayfinding point. Behind it, the
// first point is scored as any other (the old rule for every start: 0 reached, 3 missed below).
TEST(Scores, AStartPointTheVehicleBeganBesideOrPastIsPassed) {
  const std::vector<Goal> path{{0, 0}, {10, 0}, {10, 10}};
  const auto from = [&](double n, double e) {
    return score_path({{0, n, e, 0}, {1, 10, 0.5, 0}, {2, 10, 10, 0}}, path, 0.0, 2.0);
  };
  for (const auto& [n, e] : {std::pair{3.0, 0.0}, {0.0, 3.5}, {2.0, -3.0}}) {
    SCOPED_TRACE(std::to_string(n) + ", " + std::to_string(e));
    const auto s = from(n, e);
    EXPECT_TRUE(s.start_passed);
    EXPECT_EQ(s.waypoints_reached, 3);
    EXPECT_EQ(s.waypoints_missed, 0);
    EXPECT_TRUE(s.start_excluded);
    EXPECT_EQ(s.wayfinding_points, 2);
    EXPECT_NEAR(s.vrx_wayfinding, 0.25, 1e-12);  // (0.5 + 0) / 2
  }
  // Behind the first point (-3 m along the first segment): it is still to be reached.
  auto s = from(-3, 0);
  EXPECT_FALSE(s.start_passed);
  EXPECT_EQ(s.waypoints_reached, 0);
  EXPECT_EQ(s.waypoints_missed, 3);
  EXPECT_EQ(s.wayfinding_points, 3);
  // Within the visit radius: started at it, reached at once (not "passed").
  s = from(0.5, 0.5);
  EXPECT_FALSE(s.start_passed);
  EXPECT_EQ(s.waypoints_reached, 3);
  EXPECT_TRUE(s.start_excluded);
}

TEST(Scores, OnePointPathAsFollowed) {
  const std::vector<Goal> one{{10, 2}};
  const std::vector<Pose> run{{0, -5, -5, 0}, {1, 0, 2, 0}, {2, 5, 2, 0}};
  auto p = path_as_followed(one, run, 0.5);  // from the first pose at or after t = 0.5
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p[0].north, 0);
  EXPECT_DOUBLE_EQ(p[0].east, 2);
  EXPECT_DOUBLE_EQ(p[1].north, 10);
  const auto s = score_path(run, p, 0.5);
  EXPECT_DOUBLE_EQ(s.cross_track_max, 0.0);  // on the line (not 10 m: the distance to the goal)
  // Already at the point, or a longer path: unchanged.
  EXPECT_EQ(path_as_followed(one, {{0, 10, 2, 0}}, 0).size(), 1u);
  EXPECT_EQ(path_as_followed({{0, 0}, {1, 0}}, run, 0).size(), 2u);
}

TEST(Scores, MissedWaypointsAndNoCompletion) {
  const std::vector<Goal> path{{0, 0}, {10, 0}, {10, 10}};
  const std::vector<Pose> run{{0, 0, 0, 0}, {1, 8, 0, 0}, {2, 8, 8, 0}};
  const auto s = score_path(run, path, 0.0);
  EXPECT_EQ(s.waypoints_reached, 1);
  EXPECT_EQ(s.waypoints_missed, 2);
  EXPECT_DOUBLE_EQ(s.time_to_complete, -1);
  EXPECT_DOUBLE_EQ(s.final_heading_error, -1);  // no goal heading
}

TEST(Scores, VrxStationKeeping) {
  const Goal g{0, 0, true, 0};
  const std::vector<Pose> run{{0, 3, 4, 0}, {1, 0, 0, 0.5}, {2, 1, 0, 0}, {3, 0, 0, 0}};
  // Window [1, 2]: E = 0.5 and 1.
  EXPECT_DOUBLE_EQ(vrx_station_keeping(run, g, 1, 2), 0.75);
  EXPECT_DOUBLE_EQ(max_distance(run, g, 0, 3), 5);
  EXPECT_DOUBLE_EQ(vrx_station_keeping(run, g, 10, 20), -1);
}

}  // namespace
}  // namespace tiller::scores

// corner_scores on a hand-made run: an L path (0,0) -> (100,0) -> (100,100), the vehicle at
// 1 m/s, 0.5 m right of the first leg (east), overshooting the corner by 2 m north, then 0.2 m
// left of the second leg (north of it).
TEST(CornerScores, HandMadeRun) {
  using namespace tiller::scores;
  std::vector<Goal> path = {{0, 0}, {100, 0}, {100, 100}};
  std::vector<Pose> run;
  double t = 0;
  for (int n = 0; n <= 100; ++n) run.push_back({t++, double(n), 0.5, 0});    // leg 1
  run.push_back({t++, 102, 2, 0});                                           // overshoot 2 m
  for (int e = 3; e <= 100; ++e) run.push_back({t++, 100.2, double(e), 0});  // leg 2
  const auto c = corner_scores(run, path, 0, 60);
  ASSERT_EQ(c.passage.size(), 3u);
  EXPECT_DOUBLE_EQ(c.passage[0], 0);
  EXPECT_DOUBLE_EQ(c.passage[1], 100);  // (100, 0.5): 0.5 m from the corner
  EXPECT_DOUBLE_EQ(c.passage[2], 199);  // (100.2, 100)
  ASSERT_EQ(c.overshoot.size(), 1u);
  EXPECT_NEAR(c.overshoot[0], 2.0, 1e-12);
  EXPECT_NEAR(c.max_overshoot, 2.0, 1e-12);
  // Steady: leg 1 from t = 60 to 10 m before its end, north 90 (31 samples at 0.5 m); leg 2
  // from 160 (east 61) to east 90 at t = 189 (30 at 0.2).
  EXPECT_EQ(c.steady_samples, 61);
  EXPECT_NEAR(c.steady_cross_track_rms, std::sqrt((31 * 0.25 + 30 * 0.04) / 61), 1e-12);
  EXPECT_DOUBLE_EQ(c.weaving, 0);  // a constant heading
  // Without the end margin (the definition before issue 35): up to each passage.
  const auto whole = corner_scores(run, path, 0, 60, 1e300, 0);
  EXPECT_EQ(whole.steady_samples, 81);
  EXPECT_NEAR(whole.steady_cross_track_rms, std::sqrt((41 * 0.25 + 40 * 0.04) / 81), 1e-12);
}

// The window leaves out the next turn: a boat that holds 0.1 m off the leg and starts its turn
// 4 m before the corner (cutting inside, up to 2 m off the first leg's line at the corner, as a
// wheel-over point does) scores 0.1 m, not the cut. And a heading weaving as 0.1 sin(0.5 t)
// scores its RMS rate 0.05 / sqrt 2 (sampled at 10 Hz: within 1e-3 of it).
TEST(CornerScores, TheNextTurnIsNotTheLegsAndWeavingIsTheHeadingRate) {
  using namespace tiller::scores;
  std::vector<Goal> path = {{0, 0}, {200, 0}, {200, 200}};
  std::vector<Pose> run;
  for (int i = 0; i <= 1960; ++i) {  // 1 m/s north, 0.1 m right of the leg, 10 Hz
    const double t = i * 0.1;
    run.push_back({t, t, 0.1, 0.1 * std::sin(0.5 * t)});
  }
  for (int i = 1; i <= 40; ++i) {  // the cut: from (196, 0.1) to (200, 2.1)
    const double t = 196 + i * 0.1;
    run.push_back({t, 196 + i * 0.1, 0.1 + i * 0.05, 0});
  }
  for (int i = 1; i <= 2000; ++i) {  // the second leg, 0.1 m short of its line (north 199.9)
    const double t = 200 + i * 0.1;
    run.push_back({t, 199.9, 2.1 + i * 0.1, 0});
  }
  const auto c = corner_scores(run, path, 0);
  EXPECT_NEAR(c.steady_cross_track_rms, 0.1, 1e-12);
  const auto whole = corner_scores(run, path, 0, 60, 1e300, 0);
  EXPECT_GT(whole.steady_cross_track_rms, 0.14);  // the cut counted
  // Weaving: leg 1 (the sine, t 60-190) and leg 2 (0); RMS over both windows' rate samples.
  const int n1 = 1300, n2 = static_cast<int>(c.steady_samples) - 1301 - 1;
  const double r1 = 0.05 / std::sqrt(2.0);
  EXPECT_NEAR(c.weaving, r1 * std::sqrt(double(n1) / (n1 + n2)), 1e-3);
}

// The same run followed by station keeping at the goal: 20 s 1 m off the second leg's line,
// then exactly on the goal. Without an end the goal's closest approach is at the end of the
// hold (220 s) and the hold counts as the last leg; with end = the completion (199 s), the
// scores are as above.
TEST(CornerScores, StationKeepingAfterTheEndDoesNotCount) {
  using namespace tiller::scores;
  std::vector<Goal> path = {{0, 0}, {100, 0}, {100, 100}};
  std::vector<Pose> run;
  double t = 0;
  for (int n = 0; n <= 100; ++n) run.push_back({t++, double(n), 0.5, 0});
  run.push_back({t++, 102, 2, 0});
  for (int e = 3; e <= 100; ++e) run.push_back({t++, 100.2, double(e), 0});
  for (int k = 0; k < 20; ++k) run.push_back({t++, 101, 100, 0});
  run.push_back({t++, 100, 100, 0});
  // (end_margin_m 0: the margin would also leave the hold out, as it is beyond east 90.)
  const auto all = corner_scores(run, path, 0, 60, 1e300, 0);
  EXPECT_DOUBLE_EQ(all.passage[2], 220);
  EXPECT_EQ(all.steady_samples, 102);
  const auto c = corner_scores(run, path, 0, 60, 199, 0);
  EXPECT_DOUBLE_EQ(c.passage[2], 199);
  EXPECT_EQ(c.steady_samples, 81);
  EXPECT_NEAR(c.steady_cross_track_rms, std::sqrt((41 * 0.25 + 40 * 0.04) / 81), 1e-12);
  EXPECT_NEAR(c.max_overshoot, 2.0, 1e-12);
}
