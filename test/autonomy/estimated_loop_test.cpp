// Closed loop on estimated state (issue 14 item 5) across the Otter missions the missions matrix
// flies on the truth (config/missions/*.yaml: default, long_course, vrx_wayfinding,
// station_keeping), in still water and in a 0.3 m/s current toward each of 8 directions: each
// spec flown on the simulator's truth and on tiller-nav's odometry from the simulated sensors
// (GNSS 2.5 m CEP at 5 Hz, consumer IMU, heading: config/sim/sensors/usv.yaml,
// config/nav/usv_sim.yaml) through lib/runtool's run() (tiller-run), and compared. Against the
// truth run of the same spec, the targets:
//   * estimation error RMS <= 0.5 m and <= 1 deg;
//   * no waypoint missed, on the estimate (what the follower saw) and on the truth;
//   * time to complete <= 1.5x the truth run's;
//   * cross-track RMS on the estimate (to the path as the follower followed it) <= 1.5x the
//     truth run's: the controller's quality apart from the estimator's;
//   * true cross-track RMS <= the truth run's + the estimation RMS.
// Where a target is not met, kGaps holds the measured worst and the test asserts that (10 %
// margin) instead, so that it is neither hidden nor allowed to grow; the test prints every
// number and says "NOT MET" on those lines. docs/navigation.md has the table and the causes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/angles.hpp"
#include "runtool/run.hpp"
#include "runtool/sweep.hpp"

namespace tiller::runtool {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

// The measured worst where a target is not met (2026-12-03, seed 1, config/nav/usv_sim.yaml
// with the sway constraint, every estimated run behind the start gate at 0.3 m; still water, the
// worst of the 8 directions), asserted with a 10 % margin; 0: the target holds there.
//   * estimate cross-track ratio, long_course in still water (1.58x): the truth run's
//     cross-track is 0.042 m, nearly all at the corners (0.0004 m on the straights), while the
//     estimate wanders across the path at 0.01 to 1 Hz with the GNSS's noise, mostly its
//     velocity noise (0.05 m/s at 5 Hz) integrated into the position: 1.62x without the sway
//     constraint, 1.54x with it at 0.02 m/s (over-confident in an outage), 1.29x with a GNSS
//     velocity ten times cleaner, 1.48x (seeds 0, 2, 3: 2.00, 1.60, 1.57x) with a perfect IMU
//     and heading: a floor set by the receiver (docs/navigation.md, "The floor under
//     long_course's ratio"). Every other mission and current: <= 1.31x.
//   * truth missed, long_course in a current toward 135, 180, 225 deg: the estimate passes within
//     the 1 m visit radius, the boat (0.28 m estimation RMS, up to 1 m at times) just outside.
//     Misses are counted beyond the truth run's of the same drifted start (vrx_wayfinding toward
//     45 deg misses 4 on both).
struct Gap {
  const char* mission;
  double est_xte_ratio_still = 0, est_xte_ratio_current = 0;  // target 1.5
  double true_xte_excess = 0;  // true XTE / (truth XTE + estimation RMS), target 1
  int truth_missed = 0;        // target 0
};
const Gap kGaps[] = {
    {"default", 0, 0, 0, 0},
    {"long_course", 1.58, 0, 0, 2},
    {"vrx_wayfinding", 0, 0, 0, 0},
    {"station_keeping", 0, 0, 0, 0},
};

struct Water {
  std::string name;
  std::vector<std::string> args;
};

std::vector<Water> waters() {
  std::vector<Water> w = {{"still", {"--current-speed", "0"}}};
  for (int d = 0; d < 360; d += 45)
    w.push_back({"0.3 toward " + std::to_string(d),
                 {"--current-speed", "0.3", "--current-toward-deg", std::to_string(d)}});
  return w;
}

RunSpec spec(const std::string& mission, const Water& w, double settle_s) {
  RunSpec s;
  s.mission_file = kSrc + "/config/missions/" + mission + ".yaml";
  s.sim_args = w.args;
  s.settle_s = settle_s;
  return s;
}

// The start gate the launch files on an estimate use (tiller-mission --start-std-m 0.3): the
// mission waits for tiller-nav's horizontal position 1-sigma <= 0.3 m (about 12 s of 5 Hz fixes
// from the first; the filter's steady state is 0.23 m).
constexpr double kStartStdM = 0.3;

// One pair: on the estimate with the start gate, and on the truth with the vehicle left alone
// (no thrust) for as long as the gate kept the estimated run waiting, so both start from the same
// drift.
std::pair<RunOutcome, RunOutcome> fly_pair(const std::string& mission, const Water& w) {
  RunSpec es = spec(mission, w, 0);
  es.sim_args.insert(es.sim_args.end(), {"--odometry", "estimated"});
  es.start_gate.enabled = true;
  es.start_gate.max_position_std_m = kStartStdM;
  const RunOutcome e = run(es);
  const RunOutcome t = run(spec(mission, w, std::max(e.started_at, 0.0)));
  return {t, e};
}

// The numbers compared, printed as one line.
struct Compared {
  double time_ratio, est_xte_ratio, true_xte_excess;
  int truth_missed, est_missed;  // beyond the truth run's
};

Compared compare(const std::string& mission, const std::string& water, const RunOutcome& t,
                 const RunOutcome& e) {
  const auto& tp = t.scores.path_scores;
  const auto& ep = e.scores.path_scores;
  const auto& on = *e.scores.estimate_path_scores;
  const double est = e.scores.position_error_rms;
  // Waypoints missed beyond the truth run's (both start from the same drift; the in-order count
  // of a drifted start can miss some on the truth too).
  const Compared c{
      ep.time_to_complete / tp.time_to_complete, on.cross_track_rms / tp.cross_track_rms,
      ep.cross_track_rms / (tp.cross_track_rms + est), ep.waypoints_missed - tp.waypoints_missed,
      on.waypoints_missed - tp.waypoints_missed};
  const bool met = c.time_ratio <= 1.5 && c.est_xte_ratio <= 1.5 && c.true_xte_excess <= 1 &&
                   c.truth_missed == 0 && c.est_missed == 0 && est <= 0.5 &&
                   e.scores.heading_error_rms <= deg_to_rad(1.0);
  std::printf(
      "%-15s %-15s time %6.1f -> %6.1f s (%.2fx); xte %.3f -> true %.3f, on the estimate "
      "%.3f m (%.2fx); final %.3f -> %.3f m; estimation %.3f m (max %.2f), %.2f deg; missed "
      "%d -> %d (on the estimate %d)%s\n",
      mission.c_str(), water.c_str(), tp.time_to_complete, ep.time_to_complete, c.time_ratio,
      tp.cross_track_rms, ep.cross_track_rms, on.cross_track_rms, c.est_xte_ratio,
      tp.final_position_error, ep.final_position_error, est, e.scores.position_error_max,
      rad_to_deg(e.scores.heading_error_rms), tp.waypoints_missed, ep.waypoints_missed,
      on.waypoints_missed, met ? "" : "  NOT MET");
  return c;
}

// The targets that hold everywhere, for one pair of runs.
void expect_common_targets(const RunOutcome& t, const RunOutcome& e) {
  ASSERT_TRUE(t.completed);
  ASSERT_TRUE(e.completed);
  ASSERT_TRUE(e.estimated);
  ASSERT_TRUE(e.scores.estimated());
  ASSERT_TRUE(e.scores.estimate_path_scores.has_value());
  EXPECT_GT(e.scores.estimation_samples, 1000u);
  EXPECT_LE(e.scores.position_error_rms, 0.5);
  EXPECT_LE(e.scores.heading_error_rms, deg_to_rad(1.0));
  EXPECT_LE(e.scores.estimate_path_scores->waypoints_missed, t.scores.path_scores.waypoints_missed);
  EXPECT_EQ(e.scores.path_scores.waypoints_missed + e.scores.path_scores.waypoints_reached,
            t.scores.path_scores.waypoints_missed + t.scores.path_scores.waypoints_reached);
  EXPECT_LE(e.scores.path_scores.time_to_complete, 1.5 * t.scores.path_scores.time_to_complete);
  EXPECT_DOUBLE_EQ(e.dead_reckoning_s, 0.0);
  EXPECT_DOUBLE_EQ(e.odometry_invalid_s, 0.0);
  EXPECT_EQ(e.disarm_requests, 0u);
}

TEST(EstimatedLoop, ShippedMissionsInStillWaterAndInACurrent) {
  for (const Gap& g : kGaps) {
    double worst_current_ratio = 0;
    for (const Water& w : waters()) {
      SCOPED_TRACE(std::string(g.mission) + ", " + w.name);
      const auto [t, e] = fly_pair(g.mission, w);
      expect_common_targets(t, e);
      if (HasFatalFailure()) return;
      // The gate opened once the filter had converged: about 12 s of fixes, the same in every
      // water (the estimate's covariance does not depend on the current).
      EXPECT_GE(e.started_at, 8.0);
      EXPECT_LE(e.started_at, 16.0);
      EXPECT_NEAR(e.scores.start, e.started_at, 0.05);  // the path came with the start
      EXPECT_NEAR(t.scores.start, e.started_at, 1.05);  // the truth run left alone as long
      const Compared c = compare(g.mission, w.name, t, e);
      const bool still = w.name == "still";
      const double ratio = still ? g.est_xte_ratio_still : g.est_xte_ratio_current;
      EXPECT_LE(c.est_xte_ratio, ratio > 0 ? 1.1 * ratio : 1.5);
      EXPECT_LE(c.true_xte_excess, g.true_xte_excess > 0 ? 1.1 * g.true_xte_excess : 1.0);
      EXPECT_LE(c.truth_missed, g.truth_missed);
      if (!still) worst_current_ratio = std::max(worst_current_ratio, c.est_xte_ratio);
    }
    // A gap that closed is worth knowing: the list is then out of date.
    if (g.est_xte_ratio_current > 0 && worst_current_ratio <= 1.5)
      std::printf("%s: the cross-track target now holds in every current direction\n", g.mission);
  }
}

// The same in still water with the simulator and tiller-nav running 20 s alone before the mission
// starts (RunSpec::settle_s; in a current the boat would drift 6 m from the mission's start):
// without the start's convergence the cross-track on the estimate is within 1.5x of the truth
// run's on every mission but long_course (the estimate's wander), and station_keeping's true
// cross-track within the truth's plus the estimation RMS (measured with the sway constraint
// 1.08, 1.55, 1.19, 1.19x, without it 1.09, 1.60, 1.22, 1.19x; station_keeping's true
// cross-track 0.316 <= 0.687 m; before the start gate and the settle 2.72, 3.09, 2.53, 5.05x and
// 1.256 > 0.694 m).
TEST(EstimatedLoop, AfterASettleTheStartTransientIsGone) {
  const Water still{"still, settled", {"--current-speed", "0"}};
  for (const char* m : {"default", "long_course", "vrx_wayfinding", "station_keeping"}) {
    SCOPED_TRACE(m);
    RunSpec s = spec(m, still, 20);
    const auto t = run(s);
    EXPECT_TRUE(replay_manifest(s, t.files).empty());  // a replay starts every process at once
    s.sim_args.insert(s.sim_args.end(), {"--odometry", "estimated"});
    const auto e = run(s);
    expect_common_targets(t, e);
    if (HasFatalFailure()) return;
    EXPECT_NEAR(t.scores.start, 20.0, 0.1);  // the path came after the settle
    const Compared c = compare(m, still.name, t, e);
    EXPECT_LE(c.est_xte_ratio, std::string(m) == "long_course" ? 1.1 * 1.55 : 1.5);
    EXPECT_LE(c.true_xte_excess, 1.0);
    // Truth missed: vrx_wayfinding settled misses 3 of its 6 on the truth (every one reached on
    // the estimate): the 1 m visit radius against a 0.4 m estimation RMS, as long_course above.
    EXPECT_LE(c.truth_missed, std::string(m) == "vrx_wayfinding" ? 3 : 0);
  }
}

// The missions matrix's column: a sweep's rows on estimated state carry the cross-track on the
// estimate and the waypoints it missed, the same as the single runs' scores.
TEST(EstimatedLoop, SweepRowsCarryTheCrossTrackOnTheEstimate) {
  RunSpec s = spec("default", {"current", {"--current-speed", "0.3"}}, 0);
  s.sim_args.insert(s.sim_args.end(), {"--odometry", "estimated"});
  const std::vector<Axis> axes = {parse_axis("current-toward-deg=90,180")};
  const auto rows = sweep(s, axes, 2);
  ASSERT_EQ(rows.size(), 2u);
  for (const Row& r : rows) {
    ASSERT_TRUE(r.ok) << r.error;
    const auto o = run(spec_at(s, axes, r.index));
    const auto& on = *o.scores.estimate_path_scores;
    EXPECT_EQ(r.est_xte_rms, on.cross_track_rms);
    EXPECT_EQ(r.est_missed, on.waypoints_missed);
    EXPECT_EQ(r.est_rms, o.scores.position_error_rms);
    EXPECT_GT(r.est_xte_rms, 0.0);
    EXPECT_NE(r.est_xte_rms, r.xte_rms);  // the estimate's, not the truth's
  }
  // On the truth: no estimate columns.
  RunSpec t = spec("default", {"still", {"--current-speed", "0"}}, 0);
  const Row truth = row_of(run(t));
  EXPECT_EQ(truth.est_rms, -1.0);
  EXPECT_EQ(truth.est_xte_rms, -1.0);
  EXPECT_EQ(truth.est_steady_rms, -1.0);
  const std::string table = csv(axes, rows);
  EXPECT_NE(table.find(",est_xte_rms,est_steady_rms,est_missed,"), std::string::npos) << table;
}

}  // namespace
}  // namespace tiller::runtool
