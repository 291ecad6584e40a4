// Flying both seed ROVs from the joystick presets, in one process on simulated time:
// TeleopNode (replay input: TILLER_JOYSTICK injected as a recorded stick would give it) ->
// MixerNode -> EscNode (sim backend). Arming from the stick's button; the pilot's motions give
// the signs of the seeds' tables on the ESC outputs:
//   seed 000 (4 thrusters at 45 deg, int16 throttle): exact values, hand computed;
//   seed 001 ([F, LF, RF, B, LB, RB], pulses): forward [0,1,1,0,1,1], strafe right
//   [0,1,-1,0,-1,1], yaw clockwise [0,1,-1,0,1,-1], elevate up [1,0,0,1,0,0], pitch up
//   [1,0,0,-1,0,0] (seed 001's tables; + = pushing along the thruster's direction).
#include <gtest/gtest.h>

#include "flight.hpp"

namespace tiller {
namespace {

using e2e::Flight;
using e2e::signs;

TEST(FlyLockstep, Seed000RovFromTheExtreme3dPro) {
  Flight f("extreme3dpro_seed000.yaml", "config/mixer/seed000_rov4.yaml",
           "config/esc/seed000_sim.yaml");
  f.hold(500);
  ASSERT_EQ(f.out.n_channels, 4);
  EXPECT_FALSE(f.out.armed);
  f.js.axes[1] = -32767;  // full forward while disarmed: nothing
  f.hold(200);
  for (int v : f.out.value) EXPECT_EQ(v, 0);
  f.centre();
  f.hold(100);
  f.press(6);  // arm
  ASSERT_TRUE(f.arm.armed) << f.arm.reason;
  const int F = 32767;
  struct Case {
    int x, y;
    std::vector<int> expected;  // t1..t4, int16 throttle
  };
  for (const Case& c : std::vector<Case>{{0, -32767, {F, F, -F, -F}},
                                         {32767, 0, {-F, F, F, -F}},
                                         {32767, -32767, {0, F, 0, -F}},
                                         {-32767, 32767, {0, -F, 0, F}},
                                         {0, 0, {0, 0, 0, 0}}}) {
    f.js.axes[0] = static_cast<std::int16_t>(c.x);
    f.js.axes[1] = static_cast<std::int16_t>(c.y);
    f.hold(100);
    for (int i = 0; i < 4; ++i) {
      // Not "t" + std::to_string(...): GCC 12 at -O3 raises a false -Werror=restrict inside
      // that std::string operator+ (GCC bugs 105329 / 105651).
      std::string name = std::to_string(i + 1);
      name.insert(0, 1, 't');
      EXPECT_NEAR(f.value(name), c.expected[static_cast<std::size_t>(i)], 1)
          << "stick " << c.x << "," << c.y << " thruster t" << i + 1;
    }
  }
  // Half forward: the demand is the linear stick value (0.4737003 after the deadzone, see
  // teleop_node_test), and seed 000's second condition makes the throttle that fraction of full.
  f.js.axes[1] = -16384;
  f.hold(100);
  EXPECT_NEAR(f.value("t1"), 0.4737003 * F, 2);
  EXPECT_NEAR(f.value("t3"), -0.4737003 * F, 2);
  f.centre();
  f.hold(100);
  f.press(1);  // disarm
  EXPECT_FALSE(f.arm.armed);
}

TEST(FlyLockstep, Seed001RovFromTheExtreme3dProFiveDof) {
  Flight f("extreme3dpro_seed001.yaml", "config/mixer/seed001_rov6.yaml",
           "config/esc/seed001_sim.yaml");
  f.hold(300);
  f.press(6);
  ASSERT_TRUE(f.arm.armed) << f.arm.reason;
  const std::vector<std::string> order = {"F", "LF", "RF", "B", "LB", "RB"};
  struct Case {
    const char* motion;
    int axis;  // -1: a button
    int value;
    std::vector<int> table;
  };
  const std::vector<Case> cases = {
      {"forward", 1, -32767, {0, 1, 1, 0, 1, 1}},
      {"strafe right", 0, 32767, {0, 1, -1, 0, -1, 1}},
      {"yaw clockwise", 2, 32767, {0, 1, -1, 0, 1, -1}},
      {"elevate up", 5, -32767, {1, 0, 0, 1, 0, 0}},
      {"pitch up", -1, 4, {1, 0, 0, -1, 0, 0}},
  };
  for (const Case& c : cases) {
    f.centre();
    f.hold(100);
    if (c.axis >= 0) {
      f.js.axes[static_cast<std::size_t>(c.axis)] = static_cast<std::int16_t>(c.value);
    } else {
      f.js.buttons[static_cast<std::size_t>(c.value)] = true;
    }
    f.hold(100);
    // Where the seed's table moves a thruster, it moves it that way. Where the table says 0,
    // the mixer may still use it: the vectored thrusters sit 0.085 m below the centre, so a
    // horizontal force also pitches the vehicle and the geometry allocator trims that moment
    // with F and B (the mixer's choice; not the teleop's concern).
    const std::vector<int> got = signs(f.u(), order);
    for (std::size_t i = 0; i < order.size(); ++i) {
      if (c.table[i] != 0) {
        EXPECT_EQ(got[i], c.table[i]) << c.motion << ": " << order[i];
      }
    }
    EXPECT_EQ(f.out.unit, esc_output_t::UNIT_PULSE_US);
    // Full stick reaches full output on the thrusters that move (seed 001 scales a group only
    // when a value exceeds 1).
    double peak = 0;
    for (const auto& [n, v] : f.u()) peak = std::max(peak, std::abs(v));
    EXPECT_GT(peak, 0.75) << c.motion;
  }
  f.centre();
  f.hold(100);
  for (const auto& [n, v] : f.u()) EXPECT_EQ(v, 0.0) << n;
  EXPECT_EQ(f.value("F"), 1500);
}

}  // namespace
}  // namespace tiller
