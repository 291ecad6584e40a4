// tiller-tune end to end in the simulator (issue 35's targets): the manoeuvres of
// config/pilot/tune_usv.yaml flown through the pilot path on the Otter and on a vehicle the gains
// were not tuned on (mass x 1.3, damping x 1.5), identified within 10 % of the simulator's
// model; the proposed gains, written as files, fly the MSS Otter course on the unseen vehicle
// within 1.2x the hand-tuned figures on the Otter (steady cross-track, time; no waypoint missed)
// and with less corner overshoot and final error than the Otter's own gains on it, in still water
// and in a 0.3 m/s current from six directions (every run in this process, the same code).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runtime/app.hpp"
#include "runtool/run.hpp"
#include "sim/sim_node.hpp"
#include "tune/drive.hpp"
#include "tune/propose.hpp"
#include "tune/record.hpp"
#include "tune/report.hpp"
#include "tune/text_edit.hpp"

namespace tiller::tune {
namespace {

namespace fs = std::filesystem;
const std::string kSrc = TILLER_SOURCE_DIR;

struct Case {
  double mass, damping;
};

Identified identify_on(const Case& c, std::array<AxisTruth, kAxes>& truth, double& tc,
                       std::array<double, kAxes>& top, const std::string& vehicle = "otter",
                       const std::string& script = "tune_usv",
                       const std::string& teleop = "gamepad_blueboat") {
  DriveSpec s;
  s.vehicle_file = kSrc + "/config/vehicles/" + vehicle + ".yaml";
  s.script_file = kSrc + "/config/pilot/" + script + ".yaml";
  s.teleop_file = kSrc + "/config/teleop/" + teleop + ".yaml";
  s.sim_file = kSrc + "/config/sim/sim.yaml";
  s.sim_args = {"--mass-scale", std::to_string(c.mass), "--damping-scale",
                std::to_string(c.damping)};
  const DriveOutcome o = drive(s);
  EXPECT_TRUE(o.done) << o.why;
  const SimVehicle sv = load_sim_vehicle_file(s.vehicle_file);
  const Record r = record_from_events(o.events, sv.vehicle);
  SimParams sp;
  sp.mass_scale = c.mass;
  sp.damping_scale = c.damping;
  truth = model_axes(scaled_dynamics(sv.dynamics, sp));
  tc = sv.dynamics.thruster_time_constant_s;
  const Identified id = identify(r);
  top = fastest(r, id);
  std::printf("mass x%.1f, damping x%.1f:\n%s", c.mass, c.damping,
              identify_report(id, truth, tc, top, "simulator").c_str());
  return id;
}

void expect_within_10_percent(const Identified& id, const std::array<AxisTruth, kAxes>& truth,
                              double tc, const std::array<double, kAxes>& top) {
  ASSERT_TRUE(id.axis[kSurge].identified) << id.axis[kSurge].why;
  ASSERT_TRUE(id.axis[kYaw].identified) << id.axis[kYaw].why;
  const Differences d = differences(id, truth, tc, top);
  EXPECT_LT(std::fabs(d.axis[kSurge][0]), 0.10) << "surge mass";
  EXPECT_LT(std::fabs(d.axis[kSurge][1]), 0.10) << "surge linear damping";
  EXPECT_LT(std::fabs(d.axis[kSurge][3]), 0.10) << "surge drag at the fastest speed flown";
  EXPECT_LT(std::fabs(d.axis[kYaw][0]), 0.10) << "yaw inertia";
  EXPECT_LT(std::fabs(d.axis[kYaw][1]), 0.10) << "yaw linear damping";
  EXPECT_LT(std::fabs(d.axis[kYaw][2]), 0.10) << "yaw quadratic damping";
  EXPECT_LT(std::fabs(d.time_constant), 0.10) << "thruster time constant";
  // The Otter cannot push sideways: sway is reported, not guessed.
  EXPECT_FALSE(id.axis[kSway].identified);
}

TEST(TuneSim, IdentifiesTheOtterWithin10Percent) {
  std::array<AxisTruth, kAxes> truth;
  double tc = 0;
  std::array<double, kAxes> top;
  const Identified id = identify_on({1.0, 1.0}, truth, tc, top);
  expect_within_10_percent(id, truth, tc, top);
}

// The BlueROV2 from config/pilot/tune_rov.yaml: heave (with the weight less buoyancy), surge,
// sway and yaw. The one-axis model leaves out the 6-DOF couplings (the damping centre 4 cm below
// the origin turns a sway into a roll): the drags and heave come within 10 %, the sway mass and
// yaw inertia do not (-18 %, -13 %; docs/tuning.md), so only what holds is asserted.
TEST(TuneSim, AnRovsHeaveAndDragsFromItsManoeuvres) {
  std::array<AxisTruth, kAxes> truth;
  double tc = 0;
  std::array<double, kAxes> top;
  const Identified id =
      identify_on({1.0, 1.0}, truth, tc, top, "bluerov2", "tune_rov", "extreme3dpro_bluerov2");
  const Differences d = differences(id, truth, tc, top);
  for (int x = 0; x < kAxes; ++x) {
    ASSERT_TRUE(id.axis[static_cast<std::size_t>(x)].identified) << kAxisName[x];
    EXPECT_LT(std::fabs(d.axis[static_cast<std::size_t>(x)][3]), 0.10)
        << kAxisName[x] << " drag at the fastest speed flown";
  }
  EXPECT_LT(std::fabs(d.axis[kHeave][0]), 0.10) << "heave mass";
  EXPECT_LT(std::fabs(d.axis[kSurge][0]), 0.10) << "surge mass";
  EXPECT_NEAR(id.axis[kHeave].bias.value, truth[kHeave].bias, 0.1) << "weight less buoyancy, N";
}

TEST(TuneSim, IdentifiesAnUnseenVehicleAndItsGainsFlyTheCourse) {
  std::array<AxisTruth, kAxes> truth;
  double tc = 0;
  std::array<double, kAxes> top;
  const Identified id = identify_on({1.3, 1.5}, truth, tc, top);
  expect_within_10_percent(id, truth, tc, top);

  // The proposal, written as tiller-tune identify --out writes it.
  const Proposal p =
      propose(id, kSrc + "/config/vehicles/otter.yaml", kSrc + "/config/control/otter.yaml",
              kSrc + "/config/guidance/otter.yaml");
  std::printf("%s", proposal_report(p).c_str());
  const fs::path out = fs::temp_directory_path() / ("tune_sim_test_" + std::to_string(::getpid()));
  write_proposal(p, out.string());

  const auto fly = [&](bool proposed, bool unseen, const std::vector<std::string>& current) {
    runtool::RunSpec s;
    s.mission_file = kSrc + "/config/missions/mss_otter.yaml";
    s.vehicle_file = kSrc + "/config/vehicles/otter.yaml";
    s.sim_file = kSrc + "/config/sim/sim.yaml";
    s.esc_file = kSrc + "/config/esc/otter_sim.yaml";
    s.mixer_file = kSrc + "/config/mixer/otter.yaml";
    s.control_file = proposed ? (out / "config/control/otter.yaml").string()
                              : kSrc + "/config/control/otter.yaml";
    s.guidance_file = proposed ? (out / "config/guidance/otter.yaml").string()
                               : kSrc + "/config/guidance/otter.yaml";
    s.sim_args = current;
    if (unseen)
      s.sim_args.insert(s.sim_args.end(), {"--mass-scale", "1.3", "--damping-scale", "1.5"});
    return runtool::run(s);
  };
  std::vector<std::vector<std::string>> currents = {{}};
  for (int deg = 0; deg < 360; deg += 60)
    currents.push_back({"--current-speed", "0.3", "--current-toward-deg", std::to_string(deg)});
  std::printf("%-7s %-26s %-26s %-26s\n", "current", "hand-tuned, Otter", "Otter's gains, unseen",
              "proposed, unseen");
  std::printf("%-7s", "toward");
  for (int k = 0; k < 3; ++k) std::printf(" %6s %6s %6s %6s", "over", "steady", "final", "time");
  std::printf("\n");
  double worst_ratio = 0, worst_final = 0;
  for (std::size_t i = 0; i < currents.size(); ++i) {
    runtool::RunOutcome o[3] = {fly(false, false, currents[i]), fly(false, true, currents[i]),
                                fly(true, true, currents[i])};
    std::printf("%-7s", i == 0 ? "still" : currents[i][3].c_str());
    for (const auto& r : o)
      std::printf(" %6.3f %6.4f %6.3f %6.1f", r.scores.corners.max_overshoot,
                  r.scores.corners.steady_cross_track_rms,
                  r.scores.path_scores.final_position_error, r.completed_at);
    std::printf("\n");
    const auto& h = o[0].scores;
    const auto& u = o[1].scores;
    const auto& t = o[2].scores;
    EXPECT_TRUE(o[2].completed);
    EXPECT_EQ(t.path_scores.waypoints_missed, 0);
    // Against the hand-tuned figures on the Otter: steady cross-track within 1.2x or within issue
    // 35's 0.015 m (the hand-tuned figure is a fraction of a millimetre, where 1.2x is noise), the
    // time within 1.2x.
    EXPECT_LE(t.corners.steady_cross_track_rms,
              std::max(1.2 * h.corners.steady_cross_track_rms, 0.015));
    EXPECT_LE(o[2].completed_at, 1.2 * o[0].completed_at);
    // The corners and the arrival: the heavier, more damped boat turns at 0.31 rad/s where the
    // Otter turns at 0.39, and glides and drifts farther; there the proposal must do better than
    // the Otter's own gains on it (the ratios to the Otter's figures are printed; docs/tuning.md
    // has them: up to 1.36x the overshoot and 1.45x the final error, not within 1.2x).
    EXPECT_LE(t.corners.max_overshoot, u.corners.max_overshoot + 0.01);
    EXPECT_LE(t.path_scores.final_position_error, u.path_scores.final_position_error + 0.01);
    worst_final = std::max(worst_final, t.path_scores.final_position_error /
                                            std::max(h.path_scores.final_position_error, 0.10));
    worst_ratio = std::max(worst_ratio, t.corners.max_overshoot / h.corners.max_overshoot);
  }
  std::printf(
      "proposed on the unseen vehicle / hand-tuned on the Otter, worst: overshoot %.2fx, "
      "final error %.2fx (of the larger of it and 0.10 m)\n",
      worst_ratio, worst_final);
  fs::remove_all(out);
}

}  // namespace
}  // namespace tiller::tune
