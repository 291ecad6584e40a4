// The ROV pilot modes in closed loop (issue 15, "what to build" 3): tiller-rov-control's node
// between the teleop / mixer / ESC chain and the 6-DOF simulator, in lockstep (rov_rig.hpp:
// slightly positive buoyancy, a 0.3 m/s current, disturbances). Each test prints its numbers
// (docs/flying.md, "ROV modes", has the table) and asserts the issue's:
//   depth hold: steady error <= 2 cm RMS; after a 20 N vertical force step back within 10 % of
//   the peak deviation in <= 2 s, overshoot <= 10 % of it; depth within 5 cm at full forward
//   stick; heading hold <= 1 deg RMS in the current; stabilise: roll and pitch under 1 deg
//   within 2 s of a 20 deg disturbance; no sustained oscillation at any stick input; no thrust
//   step on a switch.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "rov_rig.hpp"

namespace tiller {
namespace {

using e2e::RovRig;
using e2e::RovSetup;
using M = controller_mode_t;

// Depth error (m) against the held target.
double depth_error(const RovRig& r) {
  return r.depth() - r.rov.axes().target(2);
}

RovSetup bluerov2() {
  return e2e::rov_setup("bluerov2");
}

TEST(RovModes, DepthHoldSteadyErrorInCurrentAndBuoyancy) {
  for (const RovSetup& s : {RovSetup{}, bluerov2()}) {
    RovRig r(s);
    r.command(M::DEPTH_HOLD);
    r.run(10'000);  // settle: brake, capture, integrate the buoyancy
    ASSERT_EQ(r.rov.mode(), M::DEPTH_HOLD) << r.rov.reason();
    ASSERT_TRUE(r.rov.axes().holding(2));
    std::vector<double> e;
    r.run(30'000, [&] { e.push_back(depth_error(r)); });
    const double err = e2e::rms(e);
    std::printf(
        "%s depth hold: steady error %.4f m RMS over 30 s (target %.3f m, buoyancy +2 N, "
        "current 0.3 m/s)\n",
        s.vehicle.c_str(), err, r.rov.axes().target(2));
    EXPECT_LE(err, 0.02);
    EXPECT_EQ(r.f.mixer.active_source(), wrench_t::SOURCE_ROV_CONTROL);
  }
}

// The response to a vertical force step of `force` N (NED, + down) while holding depth.
// Noise-free odometry: with the noise on, its 1.6 mm RMS is itself more than 10 % of the peak.
void force_step(double force) {
  RovSetup s;
  s.position_std_m = s.orientation_std_deg = s.velocity_std_m_s = s.rate_std_deg_s = 0;
  RovRig r(s);
  r.command(M::DEPTH_HOLD);
  r.run(10'000);
  ASSERT_TRUE(r.rov.axes().holding(2));
  const double target = r.rov.axes().target(2);
  r.sim.set_disturbance({0, 0, force});
  std::vector<double> e;
  r.run(6'000, [&] { e.push_back(r.depth() - target); });
  double peak = 0;
  for (double x : e)
    if (std::fabs(x) > std::fabs(peak)) peak = x;
  double back = 0, overshoot = 0;  // s; m on the other side
  for (std::size_t k = 0; k < e.size(); ++k) {
    if (std::fabs(e[k]) > 0.1 * std::fabs(peak)) back = 0.01 * static_cast<double>(k + 1);
    if (e[k] * peak < 0) overshoot = std::max(overshoot, std::fabs(e[k]));
  }
  std::printf(
      "depth hold, %+.0f N step: peak %.4f m, back within 10 %% after %.2f s, "
      "overshoot %.1f %%\n",
      force, peak, back, 100 * overshoot / std::fabs(peak));
  EXPECT_LE(back, 2.0);
  EXPECT_LE(overshoot, 0.1 * std::fabs(peak));
}

TEST(RovModes, DepthHoldRecoversFromA20NStep) {
  force_step(20);
  force_step(-20);
}

TEST(RovModes, DepthHeldAtFullForwardStick) {
  RovRig r;
  r.command(M::DEPTH_HOLD);
  r.run(10'000);
  const double target = r.rov.axes().target(2);
  r.f.js.axes[1] = -32767;  // full forward
  double worst = 0;
  r.run(20'000, [&] { worst = std::max(worst, std::fabs(r.depth() - target)); });
  std::printf(
      "depth hold, full forward stick 20 s: u %.2f m/s, depth error max %.4f m, pitch "
      "%.1f deg\n",
      r.nu()[0], worst, rad_to_deg(r.eta()[4]));
  EXPECT_GT(r.nu()[0], 0.3);  // it does go forward
  EXPECT_LE(worst, 0.05);
}

TEST(RovModes, HeadingHoldInTheCurrent) {
  for (const char* v : {"seed001_rov6", "seed000_rov4"}) {
    RovSetup s = e2e::rov_setup(v);
    if (std::string(v) == "seed000_rov4") s.extra_buoyancy_n = 0;
    RovRig r(s);
    r.command(M::HEADING_HOLD);
    r.run(5'000);
    ASSERT_EQ(r.rov.mode(), M::HEADING_HOLD) << r.rov.reason();
    ASSERT_TRUE(r.rov.axes().holding(5));
    std::vector<double> e;
    r.run(30'000, [&] { e.push_back(angle_diff(r.eta()[5], r.rov.axes().target(5))); });
    const double err = rad_to_deg(e2e::rms(e));
    std::printf("%s heading hold: %.4f deg RMS over 30 s in the 0.3 m/s current\n", v, err);
    EXPECT_LE(err, 1.0);
  }
}

RovSetup rov8() {
  RovSetup s;
  s.mixer = "test/data/rov8_heavy/mixer.yaml";
  s.esc = "test/data/rov8_heavy/esc.yaml";
  s.vehicle = "test/data/rov8_heavy/vehicle.yaml";
  s.control = "test/data/rov8_heavy/control.yaml";
  return s;
}

// Tilts the vehicle by 20 deg in roll and pitch (at rest) and returns the time (s) after which
// |angle| stays under 1 deg for each of roll and pitch over the following 6 s.
std::array<double, 2> tilt_recovery(RovRig& r) {
  sim::Vector6 eta = r.eta();
  eta[3] = eta[4] = deg_to_rad(20);
  r.sim.model().reset(eta, sim::Vector6::Zero());
  std::array<double, 2> t{0, 0};
  int k = 0;
  r.run(6'000, [&] {
    ++k;
    for (int a = 0; a < 2; ++a)
      if (std::fabs(r.eta()[3 + a]) >= deg_to_rad(1)) t[static_cast<std::size_t>(a)] = 0.01 * k;
  });
  return t;
}

TEST(RovModes, StabiliseLevelsAfterA20DegreeTilt) {
  {
    RovRig r(rov8());  // every axis actuated
    r.command(M::STABILISE);
    r.run(3'000);
    ASSERT_EQ(r.rov.mode(), M::STABILISE) << r.rov.reason();
    const auto t = tilt_recovery(r);
    std::printf(
        "rov8_heavy stabilise, 20 deg tilt: roll under 1 deg after %.2f s, pitch after "
        "%.2f s\n",
        t[0], t[1]);
    EXPECT_LE(t[0], 2.0);
    EXPECT_LE(t[1], 2.0);
  }
  {
    RovRig r(bluerov2());  // roll actuated, pitch left to the righting moment
    r.command(M::STABILISE);
    r.run(3'000);
    ASSERT_EQ(r.rov.axes().role(4), control::AxisRole::kOff) << r.rov.reason();
    const auto t = tilt_recovery(r);
    std::printf(
        "bluerov2 stabilise, 20 deg tilt: roll under 1 deg after %.2f s (pitch, not "
        "actuated, passive: %.2f s)\n",
        t[0], t[1]);
    EXPECT_LE(t[0], 2.0);
  }
  {
    RovRig r;  // seed001_rov6: pitch actuated, roll left to the righting moment
    r.command(M::STABILISE);
    r.run(3'000);
    ASSERT_EQ(r.rov.axes().role(3), control::AxisRole::kOff);
    const auto t = tilt_recovery(r);
    std::printf(
        "seed001_rov6 stabilise, 20 deg tilt: pitch under 1 deg after %.2f s (roll, not "
        "actuated, passive: %.2f s)\n",
        t[1], t[0]);
    EXPECT_LE(t[1], 2.0);
  }
}

TEST(RovModes, TheFourThrusterRovIsRefusedWhatNeedsHeaveRollOrPitch) {
  RovRig r(e2e::rov_setup("seed000_rov4"));
  const struct {
    std::int8_t mode;
    const char* axis;
  } refused[] = {{M::DEPTH_HOLD, "heave (Z)"},
                 {M::SURFACE, "heave (Z)"},
                 {M::STABILISE, "roll (K) or pitch (M)"},
                 {M::RATE, "roll (K) or pitch (M)"},
                 {M::POSITION_HOLD, "heave (Z)"},
                 {M::WAYPOINTING, "heave (Z)"}};
  for (const auto& x : refused) {
    r.command(x.mode);
    r.run(100);
    EXPECT_EQ(r.rov.mode(), M::MANUAL_OPEN_LOOP);
    EXPECT_NE(r.rov.reason().find(x.axis), std::string::npos) << r.rov.reason();
    EXPECT_NE(r.rov.reason().find("refused"), std::string::npos) << r.rov.reason();
    EXPECT_EQ(r.f.mixer.active_source(), wrench_t::SOURCE_MANUAL_DEMAND);
  }
  EXPECT_EQ(r.rov.counter_value("mode.refused"), 6);
  std::printf("refused: %s\n", r.rov.reason().c_str());
  r.f.press(7);  // the preset's heading-hold button (base 8)
  r.run(100);
  EXPECT_EQ(r.rov.mode(), M::HEADING_HOLD) << r.rov.reason();
  EXPECT_EQ(r.f.mixer.active_source(), wrench_t::SOURCE_ROV_CONTROL);
}

// Every switch, with the stick held half forward and full up: the thrust moves by at most 2 N
// (5.5 % of a thruster's 36 N) per 10 ms (blend_s 0 shows what an unblended switch does:
// 62 N; 0.5 s gave 5.2 N).
TEST(RovModes, NoThrustStepOnASwitch) {
  for (double blend : {1.0, 0.0}) {  // the control file's, none
    RovSetup setup;
    setup.blend_s = blend;
    // Noise-free odometry: with it, each 20 Hz odometry update moves the depth loop's thrust
    // by up to 5 N through kd (its own ripple, not the switch's).
    setup.position_std_m = setup.orientation_std_deg = 0;
    setup.velocity_std_m_s = setup.rate_std_deg_s = 0;
    RovRig r(setup);
    r.f.js.axes[1] = -16384;  // half forward
    r.f.js.axes[5] = -32767;  // hat up: climb
    r.run(1'000);
    const double steady = e2e::thrust_step(r, 2'000);
    double worst = 0;
    std::string at;
    for (std::int8_t m : {M::STABILISE, M::DEPTH_HOLD, M::HEADING_HOLD, M::RATE, M::POSITION_HOLD,
                          M::SURFACE, M::MANUAL_OPEN_LOOP}) {
      r.command(m);
      const double s = e2e::thrust_step(r, 2'000);
      std::printf("blend %.1f s: switch to %-13s largest thrust step %.2f N per 10 ms\n", blend,
                  control::rov_mode_name(m), s);
      if (s > worst) {
        worst = s;
        at = control::rov_mode_name(m);
      }
    }
    std::printf("blend %.1f s: steady manual flight %.2f N, worst switch %.2f N (%s)\n", blend,
                steady, worst, at.c_str());
    if (blend > 0) {
      EXPECT_LE(worst, 2.0);
    }
  }
}

// No sustained oscillation at any stick input: every assisted mode, every stick axis of the
// preset at full either way for 9 s, then released for 9 s. The controlled rates (depth rate,
// pitch rate, yaw rate) less their trend swing over 6-9 s by under 0.02 (m/s, rad/s), or by
// less than 0.7 of their swing over 3-6 s: a steady motion or a slow approach is fine, a limit
// cycle (equal swings) is not.
TEST(RovModes, NoSustainedOscillationAtAnyStick) {
  struct Stick {
    const char* what;
    int axis;    // js axis, or -1
    int value;   // raw
    int button;  // js button, or -1
  };
  const Stick sticks[] = {{"forward", 1, -32767, -1}, {"back", 1, 32767, -1},
                          {"right", 0, 32767, -1},    {"left", 0, -32767, -1},
                          {"twist cw", 2, 32767, -1}, {"twist ccw", 2, -32767, -1},
                          {"hat up", 5, -32767, -1},  {"hat down", 5, 32767, -1},
                          {"nose up", -1, 0, 4},      {"nose down", -1, 0, 5}};
  double worst[3] = {0, 0, 0};
  // m/s, rad/s, rad/s. Pitch: a position hold spun by the twist in the current swings by
  // 0.08 rad/s (+-1 deg) at the spin rate (the force that holds against the current turns with
  // the body, and the horizontal thrusters sit below the CG): forced, not a limit cycle.
  const double kSmall[3] = {0.02, 0.1, 0.02};
  const char* const kWhat[3] = {"depth rate", "pitch rate", "yaw rate"};
  RovSetup quiet;  // noise-free odometry: the loop's own motion, not the sensor's jitter
  quiet.position_std_m = quiet.orientation_std_deg = 0;
  quiet.velocity_std_m_s = quiet.rate_std_deg_s = 0;
  for (std::int8_t m : {M::STABILISE, M::DEPTH_HOLD, M::HEADING_HOLD, M::RATE, M::POSITION_HOLD}) {
    RovRig r(quiet);
    r.command(m);
    r.run(3'000);
    for (const Stick& st : sticks) {
      for (int phase = 0; phase < 2; ++phase) {
        r.f.centre();
        if (phase == 0 && st.axis >= 0) r.f.js.axes[static_cast<std::size_t>(st.axis)] = st.value;
        if (phase == 0 && st.button >= 0)
          r.f.js.buttons[static_cast<std::size_t>(st.button)] = true;
        // Two 3 s windows after 3 s: the later one's swing is small, or shrinking.
        double sw[2][3];
        r.run(3'000);
        for (auto& win : sw) {
          std::vector<double> w, q, rr;
          r.run(3'000, [&] {
            const double sf = std::sin(r.eta()[3]), cf = std::cos(r.eta()[3]);
            const double sp = std::sin(r.eta()[4]), cp = std::cos(r.eta()[4]);
            w.push_back(-sp * r.nu()[0] + cp * sf * r.nu()[1] + cp * cf * r.nu()[2]);
            q.push_back(r.nu()[4]);
            rr.push_back(r.nu()[5]);
          });
          win[0] = e2e::swing(w);
          win[1] = e2e::swing(q);
          win[2] = e2e::swing(rr);
        }
        for (int k = 0; k < 3; ++k) {
          worst[k] = std::max(worst[k], sw[1][k]);
          EXPECT_TRUE(sw[1][k] < kSmall[k] || sw[1][k] < 0.7 * sw[0][k])
              << control::rov_mode_name(m) << ", " << st.what << (phase ? " released" : "") << ": "
              << kWhat[k] << " swings " << sw[0][k] << " then " << sw[1][k];
        }
      }
    }
  }
  std::printf(
      "every mode x every stick, held and released: largest swing over 6-9 s: depth "
      "rate %.3f m/s, pitch rate %.3f rad/s, yaw rate %.3f rad/s\n",
      worst[0], worst[1], worst[2]);
}

}  // namespace
}  // namespace tiller
