// tiller-run's logic (lib/runtool): the default mission gives the closed-loop harness's numbers
// (test/autonomy/harness.cpp, the lockstep runs behind closed_loop_test and missions_bench), the
// mission's start: is where the boat starts, the same spec gives the same log bytes, settings
// change what they name and refuse what they cannot, and a sweep's rows are the single runs'.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/angles.hpp"
#include "core/config.hpp"
#include "harness.hpp"
#include "plants.hpp"
#include "runtime/log.hpp"
#include "runtool/run.hpp"
#include "runtool/sweep.hpp"

namespace tiller::runtool {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;
const std::string kDefault = kSrc + "/config/missions/default.yaml";

std::string tmp(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "tiller-runtool-test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

RunSpec default_spec() {
  RunSpec s;
  s.mission_file = kDefault;
  return s;
}

// The harness's full Otter stack with the Otter's shipped configs (what tiller-run defaults to).
test::RunConfig harness_config(double current_speed, double current_from_deg) {
  test::RunConfig c;
  const auto& otter = test::plants()[0];
  c.mission_file = "config/missions/default.yaml";
  c.control_file = otter.control_file;
  c.guidance_file = otter.guidance_file;
  c.make_plant = otter.make;
  c.pose_channel = otter.pose_channel;
  c.current_speed = current_speed;
  c.current_from_deg = current_from_deg;
  return c;
}

void expect_same_scores(const RunOutcome& o, const test::RunResult& h, double tol) {
  ASSERT_TRUE(h.completed);
  ASSERT_TRUE(o.completed);
  const auto& p = o.scores.path_scores;
  EXPECT_NEAR(o.completed_at, h.completed_at, tol);
  EXPECT_NEAR(o.sim_s, h.sim_s, tol);
  EXPECT_NEAR(p.cross_track_rms, h.path.cross_track_rms, tol);
  EXPECT_NEAR(p.cross_track_max, h.path.cross_track_max, tol);
  EXPECT_NEAR(p.final_position_error, h.path.final_position_error, tol);
  EXPECT_NEAR(p.vrx_wayfinding, h.path.vrx_wayfinding, tol);
  EXPECT_NEAR(o.scores.station_keeping, h.station_vrx, tol);
  EXPECT_EQ(p.waypoints_missed, h.path.waypoints_missed);
  EXPECT_EQ(p.waypoints_reached, h.path.waypoints_reached);
}

TEST(RunTool, DefaultMissionGivesTheHarnessNumbersInStillWater) {
  const auto o = run(default_spec());
  const auto h = test::run_mission(harness_config(0.0, 0.0));
  expect_same_scores(o, h, 0.0);  // bit for bit: the same nodes, configs and order
  EXPECT_EQ(o.scores.path_scores.waypoints_reached, 5);
  EXPECT_GT(o.messages, 10000u);
}

TEST(RunTool, CurrentFlagsGiveTheHarnessNumbersInACurrent) {
  RunSpec s = default_spec();
  // The harness names where the water comes FROM (30 deg); tiller-sim where it flows (210 deg).
  s.sim_args = {"--current-speed", "0.3", "--current-toward-deg", "210"};
  const auto o = run(s);
  const auto h = test::run_mission(harness_config(0.3, 30.0));
  // Same up to the last bit of the direction (30 deg + pi vs 210 deg in radians).
  expect_same_scores(o, h, 1e-6);
  // And the current does something: the still-water run differs.
  const auto still = run(default_spec());
  EXPECT_GT(
      std::abs(o.scores.path_scores.cross_track_rms - still.scores.path_scores.cross_track_rms),
      1e-3);
}

// On estimated state the whole Otter stack flies on tiller-nav's odometry, made from the
// simulated GNSS (2.5 m CEP, 5 Hz, 0.1 s latency), IMU and heading (config/sim/sensors/usv.yaml,
// config/nav/usv_sim.yaml). The targets of issue 14: estimation error RMS <= 0.5 m and <= 1 deg
// (measured 0.37 m / 0.88 deg on default.yaml, 0.28 m / 0.52 deg on long_course.yaml with the
// start gate; 0.83 and 0.84 m before the filter used the accelerometer and the fix's latency). The
// boat follows the estimate, so its true cross-track is the truth run's plus at most the estimation
// error (the 1.5x targets on cross-track, measured per mission and current: estimated_loop_test and
// docs/navigation.md, "Closed loop on estimated state").
TEST(RunTool, EstimatedStateMeetsTheEstimationTargetsOnTheShippedMissions) {
  for (const char* mission : {"default.yaml", "long_course.yaml"}) {
    SCOPED_TRACE(mission);
    RunSpec s;
    s.mission_file = kSrc + "/config/missions/" + mission;
    s.sim_args = {"--odometry", "estimated"};
    s.start_gate.enabled = true;  // as the launch files: wait for a 1-sigma <= 0.3 m
    s.start_gate.max_position_std_m = 0.3;
    const auto o = run(s);
    ASSERT_TRUE(o.estimated);
    ASSERT_TRUE(o.completed);
    EXPECT_GT(o.started_at, 5.0);
    RunSpec ts;  // the truth, left alone as long
    ts.mission_file = s.mission_file;
    ts.settle_s = o.started_at;
    const auto truth = run(ts);
    const auto& p = o.scores.path_scores;
    const auto& t = truth.scores.path_scores;
    EXPECT_EQ(p.waypoints_missed, 0);
    EXPECT_EQ(p.waypoints_reached, t.waypoints_reached);
    EXPECT_GT(o.scores.estimation_samples, 1000u);
    EXPECT_GT(o.scores.position_error_rms, 0.05);  // an estimate, not the truth
    EXPECT_LE(o.scores.position_error_rms, 0.5);   // m
    EXPECT_LE(o.scores.heading_error_rms, deg_to_rad(1.0));
    EXPECT_LE(p.time_to_complete, 1.5 * t.time_to_complete);
    EXPECT_LE(p.cross_track_rms, t.cross_track_rms + o.scores.position_error_rms);
    EXPECT_DOUBLE_EQ(o.dead_reckoning_s, 0.0);
    EXPECT_DOUBLE_EQ(o.odometry_invalid_s, 0.0);
    EXPECT_EQ(o.disarm_requests, 0u);
    // tiller-replay replays tiller-nav too (run_cli_test: bit for bit)
    s.start_gate = {};
    EXPECT_NE(replay_manifest(s, o.files).find("\n  nav: " + o.files.nav + "\n"),
              std::string::npos);
  }
}

// A 20 s GNSS outage from 20 s into default.yaml (the shipped seed 1): the filter dead-reckons on
// the gyro and the accelerometer (position and velocity covariance growing, DEAD_RECKONING set).
// With the honest covariance of config/nav/usv_sim.yaml (process.accel_bias 1e-4; 3e-5 before,
// which under-stated the drift about twofold and kept the odometry valid throughout) the velocity
// 1-sigma passes limits.velocity_std_mps at the end of the outage: the odometry is invalid
// briefly (measured 0.2 s), the controllers give neutral meanwhile (no disarm), and when the
// fixes return the estimate converges and the mission completes at its goal. Before the aided
// INS the velocity went invalid 13 s in, the mixer disarmed and the boat stayed stopped. With the
// sway constraint (usv_sim.yaml) the velocity stays within the limit: invalid 0 s, largest error
// 3.1 m (the first fix's, at the start; without it 7.2 m, the outage's drift), final 0.51 m.
TEST(RunTool, EstimatedStateCarriesOnThroughA20sGnssOutageAndRecovers) {
  RunSpec s = default_spec();
  s.sim_args = {"--odometry", "estimated", "--gnss-outage", "20:20"};
  const auto o = run(s);
  ASSERT_TRUE(o.completed);
  EXPECT_GE(o.dead_reckoning_s, 18.0);  // 20 s less gnss.timeout_s (1 s)
  EXPECT_LE(o.dead_reckoning_s, 20.0);
  EXPECT_LE(o.odometry_invalid_s, 2.0);  // s: at the end of the outage only (measured 0.2)
  EXPECT_EQ(o.disarm_requests, 0u);
  EXPECT_EQ(o.invalid_thrust_max, 0.0);
  EXPECT_LE(o.max_setpoint_speed, o.max_speed + 1e-9);
  EXPECT_GT(o.scores.position_error_max, 1.0);   // m: dead reckoning drifts (measured 7.7)
  EXPECT_LT(o.scores.position_error_max, 10.0);  // within limits.position_std_m
  EXPECT_LT(o.scores.path_scores.final_position_error, 1.5);  // m: recovered (measured 0.75)
}

// The same outage on seeds 0-7: the velocity 1-sigma passes limits.velocity_std_mps late in the
// outage on most seeds, so tiller-nav flags the odometry invalid for a few seconds. The
// controllers then give a deliberate neutral (a valid zero wrench: armed, gate ACTIVE, no
// disarm) while the estimator says invalid, and the mission resumes by itself when the odometry
// is valid again. Before, the controllers' wrench went invalid, the mixer's gate INPUT_LOST
// disarmed 3 s later (39.74 s on seed 0, 0.38 s before the odometry was valid again) and the
// boat stayed stopped: 5 of these 8 seeds did not complete. Flown without the sway constraint
// (usv_sim.yaml's sway.enabled false): with it the velocity stays within the limit through the
// outage (odometry invalid 0 s on every one of these seeds), so the case would not happen.
// The default mission on estimated state, a 20 s GNSS outage from 20 s, without the sway
// constraint (see below).
RunSpec outage_spec(int seed) {
  RunSpec s = default_spec();
  s.sim_args = {"--odometry", "estimated", "--gnss-outage",
                "20:20",      "--seed",    std::to_string(seed)};
  s.settings = {parse_setting("nav.sway.enabled=false")};
  return s;
}

TEST(RunTool, AnOutagePastTheEstimatorsLimitGivesNeutralAndTheMissionResumes) {
  int went_invalid = 0;
  for (int seed = 0; seed < 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    RunSpec s = outage_spec(seed);
    const auto o = run(s);
    if (o.odometry_invalid_s > 0.5) ++went_invalid;
    EXPECT_LE(o.odometry_invalid_s, 8.0);  // s: only late in the 20 s outage (measured <= 4.4)
    EXPECT_EQ(o.disarm_requests, 0u);
    EXPECT_EQ(o.invalid_thrust_max, 0.0);  // neutral while invalid (after the 0.5 s timeout)
    ASSERT_TRUE(o.completed);
    EXPECT_LE(o.max_setpoint_speed, o.max_speed + 1e-9);
    EXPECT_LT(o.scores.path_scores.final_position_error, 1.5);  // m: resumed and reached the goal
  }
  EXPECT_GE(went_invalid, 4);  // the case this test is about happens (measured: 7 of 8 seeds)
}

// Issue 31, case 6 (the return): back from a 20 s outage, the first fixes moved tiller-nav's
// published position by up to 12.7 m in one step (seeds 0-7: 5.6, 6.8, 5.2, 8.7, 10.7, 5.3, 1.9,
// 12.7 m with recovery.rate_mps 0, the old jump). With the correction beyond the fix's 1-sigma
// (2.12 m per axis here) released at 0.5 m/s, no step is larger than that 1-sigma plus the
// motion of one 20 ms tick (measured 1.86-2.17 m), and every seed still completes.
TEST(RunTool, BackFromAnOutageTheEstimateReturnsWithoutAJump) {
  double worst_before = 0;
  for (int seed = 0; seed < 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    RunSpec s = outage_spec(seed);
    const auto after = run(s);
    EXPECT_LE(after.max_position_step_m, 2.12 + 0.06);  // the receiver's 1-sigma + one tick
    EXPECT_TRUE(after.completed);
    EXPECT_LT(after.scores.path_scores.final_position_error, 1.5);
    s.settings.push_back(parse_setting("nav.recovery.rate_mps=0"));
    worst_before = std::max(worst_before, run(s).max_position_step_m);
  }
  EXPECT_GT(worst_before, 10.0);  // the defect this is about (12.65 m)
}

TEST(RunTool, TheMissionStartIsWhereTheBoatStarts) {
  const std::string m = tmp("start.yaml");
  std::ofstream(m) << "name: start\nstart: {north: 5, east: -3, heading_deg: 90}\n"
                      "time_limit_s: 5\nwaypoints:\n  - [5, -3]\n  - [5, 20]\n";
  RunSpec s;
  s.mission_file = m;
  s.log_file = tmp("start.lcmlog");
  const auto o = run(s);
  EXPECT_DOUBLE_EQ(o.start_north, 5.0);
  EXPECT_DOUBLE_EQ(o.start_east, -3.0);
  EXPECT_NEAR(o.start_heading, 1.5707963267948966, 1e-12);
  ASSERT_FALSE(o.scores.poses.empty());
  EXPECT_NEAR(o.scores.poses.front().north, 5.0, 1e-3);
  EXPECT_NEAR(o.scores.poses.front().east, -3.0, 1e-3);
  EXPECT_NEAR(o.scores.poses.front().heading, 1.5707963267948966, 1e-3);
  // The sim's options win over the mission's start.
  s.sim_args = {"--north", "-2"};
  EXPECT_DOUBLE_EQ(run(s).start_north, -2.0);
  EXPECT_DOUBLE_EQ(run(s).start_east, -3.0);
}

TEST(RunTool, TheSameSpecWritesTheSameLogBytes) {
  RunSpec s = default_spec();
  s.sim_args = {"--current-speed", "0.3", "--current-toward-deg", "120"};
  s.log_file = tmp("a.lcmlog");
  const auto a = run(s);
  s.log_file = tmp("b.lcmlog");
  const auto b = run(s);
  const std::string la = bytes(tmp("a.lcmlog")), lb = bytes(tmp("b.lcmlog"));
  EXPECT_GT(la.size(), 100000u);
  EXPECT_TRUE(la == lb) << "two runs of one spec wrote different logs";
  EXPECT_EQ(a.messages, b.messages);
  // The log holds every message the run delivered.
  EXPECT_EQ(read_log(tmp("a.lcmlog")).size(), a.messages);
}

TEST(RunTool, SettingsChangeTheNamedKeyAndRefuseWhatTheyCannot) {
  RunSpec s = default_spec();
  s.settings = {parse_setting("guidance.follower.max_speed=1.0")};
  const auto slow = run(s);
  const auto base = run(default_spec());
  ASSERT_TRUE(slow.completed);
  EXPECT_GT(slow.completed_at, base.completed_at + 5);  // 1.0 m/s instead of 1.5 m/s
  const auto refused = [&](const std::string& setting, const std::string& text) {
    RunSpec b = default_spec();
    b.settings = {parse_setting(setting)};
    try {
      run(b);
      ADD_FAILURE() << setting << " was accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  refused("control.velocity_pid.yaw.k_eror=40", "velocity_pid.yaw.k_eror: unknown key");
  refused("guidance.follower.max_speed=fast", "follower.max_speed");
  refused("control.no_such_section.kp=1", "no key no_such_section");
  refused("mixer.rate_hz.x=1", "rate_hz is not a map");
  EXPECT_THROW(parse_setting("yaw.kp=1"), std::runtime_error);        // no such file
  EXPECT_THROW(parse_setting("control.yaw.kp"), std::runtime_error);  // no value
}

TEST(RunTool, MissingDefaultConfigNamesTheOptionThatSetsIt) {
  RunSpec s = default_spec();
  s.vehicle_file = "config/vehicles/seed000_rov4.yaml";  // an ROV: no guidance config
  try {
    resolve_files(s);
    FAIL() << "resolved";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the default for this vehicle; give --esc FILE"),
              std::string::npos)
        << e.what();
  }
}

TEST(RunTool, AxesParseRangesListsAndRefuseNonsense) {
  auto a = parse_axis("control.velocity_pid.yaw.k_error=20:80:4");
  EXPECT_EQ(a.values, (std::vector<std::string>{"20", "40", "60", "80"}));
  EXPECT_TRUE(a.numeric);
  a = parse_axis("guidance=otter,seed");
  EXPECT_EQ(a.values,
            (std::vector<std::string>{"config/guidance/otter.yaml", "config/guidance/seed.yaml"}));
  EXPECT_FALSE(a.numeric);
  a = parse_axis("sim.initial.position_m=[0,0,0],[1,2,0]");
  EXPECT_EQ(a.values.size(), 2u);
  EXPECT_EQ(parse_axis("current-speed=0.1:0.1:1").values, std::vector<std::string>{"0.1"});
  for (const char* bad : {"yaw=1,2", "control.x.kp", "current-speed=0:1:0",
                          "current-speed=", "speed=1:2:3", "nofile.kp=1"}) {
    EXPECT_THROW(parse_axis(bad), std::runtime_error) << bad;
  }
}

TEST(RunTool, SweepRowsAreTheSingleRunsInGridOrder) {
  RunSpec s = default_spec();
  const std::vector<Axis> axes = {parse_axis("guidance.follower.max_speed=1.2,1.5"),
                                  parse_axis("current-toward-deg=0,90")};
  s.sim_args = {"--current-speed", "0.2"};
  const auto rows = sweep(s, axes, 2);
  ASSERT_EQ(rows.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(rows[i].ok) << rows[i].error;
    EXPECT_EQ(rows[i].index, (std::vector<std::size_t>{i / 2, i % 2}));
    const Row single = row_of(run(spec_at(s, axes, rows[i].index)));
    EXPECT_EQ(rows[i].xte_rms, single.xte_rms);
    EXPECT_EQ(rows[i].time_s, single.time_s);
    EXPECT_EQ(rows[i].vrx_sk, single.vrx_sk);
  }
  EXPECT_NE(rows[0].xte_rms, rows[1].xte_rms);  // the axes change the run
  // A point that cannot run is a row with its error, the others still run.
  const auto bad = sweep(s, {parse_axis("guidance.follower.max_speed=1.5,-1")}, 2);
  ASSERT_EQ(bad.size(), 2u);
  EXPECT_TRUE(bad[0].ok);
  EXPECT_FALSE(bad[1].ok);
  EXPECT_NE(bad[1].error.find("max_speed"), std::string::npos) << bad[1].error;
}

// An ROV's mission (issue 34): the BlueROV2-class vehicle flies config/missions/rov_transect.yaml
// (three 12 m lines at 2 and 3 m depth) by tiller-rov-control's waypointing, on tiller-nav's DVL
// dead reckoning (config/nav/rov_dvl.yaml, the default for an ROV on estimated state), in a
// 0.2 m/s current toward 30 deg: every waypoint reached, the path's depth held, the goal held, and
// the run replays bit for bit (its manifest names rov-control and nav). On truth the same.
TEST(RunTool, AnRovFliesTheTransectAtDepthOnTheDvlInACurrent) {
  RunSpec s;
  s.mission_file = kSrc + "/config/missions/rov_transect.yaml";
  s.vehicle_file = kSrc + "/config/vehicles/bluerov2.yaml";
  s.sim_args = {"--odometry", "estimated", "--current-speed", "0.2", "--current-toward-deg", "30"};
  const auto o = run(s);
  ASSERT_TRUE(o.estimated);
  ASSERT_TRUE(o.rov);
  EXPECT_NE(o.files.nav.find("config/nav/rov_dvl.yaml"), std::string::npos) << o.files.nav;
  ASSERT_TRUE(o.completed);
  const auto& p = o.scores.path_scores;
  EXPECT_EQ(p.waypoints_reached, 6);
  EXPECT_EQ(p.waypoints_missed, 0);
  EXPECT_LE(p.time_to_complete, 130.0);  // 60 m at 0.4 m/s, the dive and the turns
  EXPECT_LE(p.cross_track_rms, 0.15);    // m, the truth against the path
  EXPECT_LE(p.final_position_error, 0.25);
  EXPECT_GE(o.depth_from_s, 0.0);
  EXPECT_LE(o.depth_from_s, 20.0);  // the dive to 2 m at 0.2 m/s
  EXPECT_LE(o.depth_rms_m, 0.05);
  EXPECT_LE(o.depth_max_m, 0.15);        // the change to 3 m is the reference's 0.2 m/s ramp
  EXPECT_GT(o.dead_reckoning_s, 100.0);  // all of it on the DVL
  EXPECT_EQ(o.disarm_requests, 0u);
  const std::string m = replay_manifest(s, o.files);
  EXPECT_NE(m.find("\n  rov-control: "), std::string::npos) << m;
  EXPECT_EQ(m.find("velocity-pid"), std::string::npos) << m;
  // On the truth: the same path within a few cm.
  RunSpec t = s;
  t.sim_args = {"--current-speed", "0.2", "--current-toward-deg", "30"};
  const auto ot = run(t);
  ASSERT_TRUE(ot.completed);
  EXPECT_EQ(ot.scores.path_scores.waypoints_missed, 0);
  EXPECT_LE(ot.scores.path_scores.cross_track_rms, 0.12);
  EXPECT_LE(ot.depth_rms_m, 0.05);
  EXPECT_EQ(replay_manifest(t, ot.files), "");  // a setting changed in memory (no covariance)
}

}  // namespace
}  // namespace tiller::runtool
