// A pilot flying the simulated seed ROVs, in one process on simulated time: the joystick rig of
// fly_lockstep_test (flight.hpp: TeleopNode with the Extreme 3D Pro presets -> MixerNode ->
// EscNode sim backend) plus the SimNode with config/sim/sim.yaml and the ROV's vehicle file,
// the same programs and configs as config/launch/sim_rov_joystick.yaml (seed 000) and
// sim_rov6_joystick.yaml (seed 001). Each stick motion is held for 10 s from rest and the
// simulated vehicle must move the way the pilot asked:
//   forward stick  -> surge u > 0.3 m/s, no sway or yaw to speak of
//   stick right    -> sway v > 0.2 m/s
//   twist cw       -> yaw rate r > 0.5 rad/s (seed 001; seed 000's preset has no twist)
//   hat up         -> rises: w < -0.2 m/s and depth decreasing (NED z up is negative)
//   pitch button   -> nose up: pitch > 10 deg
// Thresholds are about half of what the model reaches (printed by the test), so a sign error,
// a dead chain or a lost axis fails, while a retune of the stick shaping does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "core/angles.hpp"
#include "flight.hpp"
#include "sim/sim_node.hpp"

namespace tiller {
namespace {

using e2e::Flight;
using e2e::kSrc;

// The launch files' tiller-sim: config/sim/sim.yaml with --vehicle.
SimParams sim_params(const std::string& vehicle) {
  const auto root = config::Value::load_file(kSrc + "/config/sim/sim.yaml");
  SimParams p = load_sim_params(root);
  root.check_all_used();
  p.vehicle_file = kSrc + "/config/vehicles/" + vehicle + ".yaml";
  return p;
}

struct SimFlight {
  SimFlight(const std::string& seed, const std::string& vehicle)
      : f("extreme3dpro_" + seed + ".yaml", "config/mixer/" + vehicle + ".yaml",
          "config/esc/" + seed + "_sim.yaml"),
        sim(sim_params(vehicle), load_sim_vehicle_file(sim_params(vehicle).vehicle_file)) {
    f.ex.add(sim);
    f.hold(300);
    f.press(6);  // arm (base button 7)
  }
  // Holds the stick as `set` leaves it for `ms` from now; returns the largest pitch seen.
  double fly(const std::function<void(joystick_state_t&)>& set, int ms) {
    f.centre();
    set(f.js);
    double max_pitch = -1e9;
    for (int k = 0; k < ms / 100; ++k) {
      f.hold(100);
      max_pitch = std::max(max_pitch, sim.model().eta()[4]);
    }
    return max_pitch;
  }
  const sim::Vector6& nu() const { return sim.model().nu(); }
  const sim::Vector6& eta() const { return sim.model().eta(); }

  Flight f;
  SimNode sim;
};

void report(const char* what, const SimFlight& s) {
  std::printf(
      "%-28s u %6.3f v %6.3f w %6.3f m/s  r %6.3f rad/s  z %7.3f m  roll %5.1f pitch %5.1f\n", what,
      s.nu()[0], s.nu()[1], s.nu()[2], s.nu()[5], s.eta()[2], rad_to_deg(s.eta()[3]),
      rad_to_deg(s.eta()[4]));
}

TEST(FlySimRov, Seed000ForwardAndStrafeFromTheStickMoveTheRov) {
  {
    SimFlight s("seed000", "seed000_rov4");
    ASSERT_TRUE(s.f.arm.armed) << s.f.arm.reason;
    s.fly([](joystick_state_t& js) { js.axes[1] = -32767; }, 10'000);  // full forward
    report("seed000 forward", s);
    EXPECT_TRUE(s.sim.esc_fresh());
    EXPECT_EQ(s.sim.rejected(), 0);
    EXPECT_GT(s.nu()[0], 0.3);
    EXPECT_GT(s.eta()[0], 2.0);  // 10 s ahead
    EXPECT_LT(std::abs(s.nu()[1]), 0.05);
    EXPECT_LT(std::abs(s.nu()[5]), 0.1);
    EXPECT_LT(std::abs(s.eta()[3]), deg_to_rad(35));
    EXPECT_LT(std::abs(s.eta()[4]), deg_to_rad(35));
    // Stick released: the ROV coasts to a stop (the thrust went to zero, not to a stale value).
    s.fly([](joystick_state_t&) {}, 10'000);
    EXPECT_LT(std::abs(s.nu()[0]), 0.05);
  }
  {
    SimFlight s("seed000", "seed000_rov4");
    s.fly([](joystick_state_t& js) { js.axes[0] = 32767; }, 10'000);  // full right
    report("seed000 strafe right", s);
    EXPECT_GT(s.nu()[1], 0.2);
    EXPECT_GT(s.eta()[1], 1.5);
    EXPECT_LT(std::abs(s.nu()[0]), 0.05);
    EXPECT_LT(std::abs(s.eta()[3]), deg_to_rad(35));
  }
  {
    // Disarmed, full forward moves nothing.
    SimFlight s("seed000", "seed000_rov4");
    s.f.press(1);  // disarm
    ASSERT_FALSE(s.f.arm.armed);
    s.fly([](joystick_state_t& js) { js.axes[1] = -32767; }, 5'000);
    EXPECT_EQ(s.nu()[0], 0.0);
    EXPECT_EQ(s.sim.commanded_thrust(0), 0.0);
  }
}

TEST(FlySimRov, Seed001EveryStickAxisMovesTheRovTheRightWay) {
  {
    SimFlight s("seed001", "seed001_rov6");
    ASSERT_TRUE(s.f.arm.armed) << s.f.arm.reason;
    s.fly([](joystick_state_t& js) { js.axes[1] = -32767; }, 10'000);
    report("seed001 forward", s);
    EXPECT_EQ(s.sim.rejected(), 0);
    EXPECT_GT(s.nu()[0], 0.3);
    EXPECT_GT(s.eta()[0], 2.0);
    EXPECT_LT(std::abs(s.nu()[1]), 0.05);
    EXPECT_LT(std::abs(s.nu()[5]), 0.1);
  }
  {
    SimFlight s("seed001", "seed001_rov6");
    s.fly([](joystick_state_t& js) { js.axes[0] = 32767; }, 10'000);
    report("seed001 strafe right", s);
    EXPECT_GT(s.nu()[1], 0.2);
    EXPECT_LT(std::abs(s.nu()[0]), 0.05);
  }
  {
    SimFlight s("seed001", "seed001_rov6");
    s.fly([](joystick_state_t& js) { js.axes[2] = 32767; }, 10'000);  // twist clockwise
    report("seed001 twist clockwise", s);
    EXPECT_GT(s.nu()[5], 0.5);
    EXPECT_LT(s.nu().head<2>().norm(), 0.05);  // turns on the spot
  }
  {
    SimFlight s("seed001", "seed001_rov6");
    const double z0 = s.eta()[2];
    s.fly([](joystick_state_t& js) { js.axes[5] = -32767; }, 10'000);  // hat up: elevate
    report("seed001 elevate up", s);
    EXPECT_LT(s.nu()[2], -0.2);       // w < 0: moving up in FRD
    EXPECT_LT(s.eta()[2], z0 - 2.0);  // depth decreasing in NED
    EXPECT_LT(std::abs(s.eta()[4]), deg_to_rad(2));
  }
  {
    SimFlight s("seed001", "seed001_rov6");
    const double max_pitch = s.fly([](joystick_state_t& js) { js.buttons[4] = true; }, 10'000);
    report("seed001 pitch up", s);
    EXPECT_GT(s.eta()[4], deg_to_rad(10));  // nose up, held against the righting moment
    EXPECT_GE(max_pitch, s.eta()[4]);
    EXPECT_LT(std::abs(s.eta()[3]), deg_to_rad(2));
    EXPECT_LT(max_pitch, deg_to_rad(89));  // not flipped over
    // The other button pitches the other way.
    s.fly([](joystick_state_t& js) { js.buttons[5] = true; }, 10'000);
    report("seed001 pitch down", s);
    EXPECT_LT(s.eta()[4], -deg_to_rad(10));
  }
}

}  // namespace
}  // namespace tiller
