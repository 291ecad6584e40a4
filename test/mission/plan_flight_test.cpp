// Missions with items flown on the simulated Otter by tiller-run's lockstep run (the real node
// classes: sim, esc, mixer, mission, follower, velocity PID, station keeping), scored on the
// ground truth: a QGroundControl plan to its end, and the run-time fence's return home.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "mission/mission.hpp"
#include "runtool/run.hpp"

namespace tiller {
namespace {

std::string src(const std::string& rel) {
  return std::string(TILLER_SOURCE_DIR) + "/" + rel;
}

double miss(const std::vector<scores::Pose>& poses, const mission::MissionPoint& p) {
  double best = 1e9;
  for (const auto& q : poses) best = std::min(best, std::hypot(q.north - p.north, q.east - p.east));
  return best;
}

TEST(PlanFlight, TheHarbourPlanFliesToItsEnd) {
  runtool::RunSpec spec;
  spec.mission_file = src("config/missions/harbour.plan");
  spec.vehicle_file = src("config/vehicles/otter.yaml");
  spec.sim_file = src("config/sim/sim.yaml");
  spec.hold_s = 10;
  const auto out = runtool::run(spec);
  const auto m = mission::load_mission_file(spec.mission_file);
  ASSERT_TRUE(out.completed);
  const auto& poses = out.scores.poses;
  ASSERT_GT(poses.size(), 100u);
  // Every waypoint (and home) reached within the follower's acceptance radius (1 m).
  ASSERT_EQ(m.waypoints.size(), 5u);
  for (std::size_t k = 0; k < m.waypoints.size(); ++k) {
    const double d = miss(poses, m.waypoints[k]);
    std::printf("waypoint %zu (%.1f, %.1f): closest %.3f m\n", k, m.waypoints[k].north,
                m.waypoints[k].east, d);
    EXPECT_LT(d, 1.0) << k;
  }
  // The loiter: 10 s within 1.5 m of (10, 25) (station keeping at the point).
  double loiter = 0, before_loiter = 0, v_slow = 0, v_fast = 0;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const auto& a = poses[k - 1];
    const auto& b = poses[k];
    const double dt = b.t - a.t;
    if (std::hypot(b.north - 10, b.east - 25) < 1.5) loiter += dt;
    const double v = std::hypot(b.north - a.north, b.east - a.east) / dt;
    // Speed 1.0 m/s up to the loiter, 1.5 m/s from item 4 on (after it).
    if (loiter == 0) {
      v_slow = std::max(v_slow, v);
      before_loiter = b.t;
    } else if (loiter > 12) {
      v_fast = std::max(v_fast, v);
    }
  }
  std::printf("loiter %.1f s, max speed %.2f m/s before it (1.0 planned), %.2f after (1.5)\n",
              loiter, v_slow, v_fast);
  EXPECT_GE(loiter, 10.0);
  EXPECT_LT(v_slow, 1.15);  // 1.09 measured: the velocity PID overshoots a little
  EXPECT_GT(v_fast, 1.2);
  EXPECT_GT(before_loiter, 30.0);
  // Home at the end: the return to launch held there.
  EXPECT_LT(std::hypot(poses.back().north, poses.back().east), 1.0);
  EXPECT_EQ(out.scores.path_scores.waypoints_missed, 0);
}

// An L-shaped inclusion fence: both waypoints inside, the straight leg between them cuts the
// missing corner, so the vehicle leaves the fence on its way.
runtool::RunOutcome fly_fence(const std::string& action) {
  const std::string path = ::testing::TempDir() + "fence_" + action + ".yaml";
  std::ofstream(path) << "name: fence_" << action << R"(
time_limit_s: 120
items:
  - [30, 0]
  - [30, 5]
  - [0, 30]
fence:
  action: )" << action << R"(
  inclusion: [[[-5, -5], [-5, 35], [5, 35], [5, 8], [35, 8], [35, -5]]]
)";
  runtool::RunSpec spec;
  spec.mission_file = path;
  spec.vehicle_file = src("config/vehicles/otter.yaml");
  spec.sim_file = src("config/sim/sim.yaml");
  return runtool::run(spec);
}

TEST(PlanFlight, LeavingTheFenceAtRunTimeReturnsHome) {
  const auto out = fly_fence("return");
  EXPECT_FALSE(out.completed);  // the mission did not reach (0, 30)
  const auto& poses = out.scores.poses;
  ASSERT_FALSE(poses.empty());
  double far_out = 0;  // how far outside the fence (into the missing corner, north > 5, east > 8)
  for (const auto& p : poses)
    if (p.north > 5 && p.east > 8) far_out = std::max(far_out, std::min(p.north - 5, p.east - 8));
  std::printf("fence: %.2f m outside at most; final (%.2f, %.2f)\n", far_out, poses.back().north,
              poses.back().east);
  EXPECT_GT(far_out, 0.0);  // it did leave (the run-time check had something to catch)
  EXPECT_LT(far_out, 3.0);
  EXPECT_LT(miss(poses, mission::MissionPoint{}), 1.0);
  EXPECT_LT(std::hypot(poses.back().north, poses.back().east), 1.0);
  EXPECT_EQ(out.disarm_requests, 0u);
}

TEST(PlanFlight, LeavingTheFenceAtRunTimeHoldsOrGoesNeutral) {
  for (const char* action : {"hold", "neutral"}) {
    const auto out = fly_fence(action);
    EXPECT_FALSE(out.completed) << action;
    const auto& poses = out.scores.poses;
    ASSERT_FALSE(poses.empty());
    const auto& end = poses.back();
    std::printf("fence %s: final (%.2f, %.2f), %zu disarm requests\n", action, end.north, end.east,
                out.disarm_requests);
    // Stopped near where it left the fence: the leg (30, 5) -> (0, 30) crosses the arm's edge
    // east 8 m at north 30 - 3 * 30 / 25 = 26.4 m; not home, not at (0, 30).
    EXPECT_LT(std::hypot(end.north - 26.4, end.east - 8), 1.5) << action;
    // Hold: an ABORT, station keeping, armed; neutral: a RELEASE, the mixer disarms.
    if (std::string(action) == "hold") {
      EXPECT_EQ(out.disarm_requests, 0u);
    } else {
      EXPECT_GE(out.disarm_requests, 1u);
    }
  }
}

}  // namespace
}  // namespace tiller
