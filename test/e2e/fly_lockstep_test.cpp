// Flying both seed ROVs from the joystick presets, in one process on simulated time:
// TeleopNode (replay input: TILLER_JOYSTICK injected as a recorded stick would give it) ->
// MixerNode -> EscNode (sim backend). Arming from the stick's button; the pilot's motions give
// the signs of the seeds' tables on the ESC outputs:
//   seed 000 (4 thrusters at 45 deg, int16 throttle): exact values, hand computed;
//   seed 001 ([F, LF, RF, B, LB, RB], pulses): forward [0,1,1,0,1,1], strafe right
//   [0,1,-1,0,-1,1], yaw clockwise [0,1,-1,0,1,-1], elevate up [1,0,0,1,0,0], pitch up
//   [1,0,0,-1,0,0] (seed 001's tables; + = pushing along the thruster's direction).
#include <gtest/gtest.h>

#include <map>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/joystick_state_t.hpp>

#include "esc/esc_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

class Flight {
 public:
  Flight(const std::string& teleop_cfg, const std::string& mixer_cfg, const std::string& esc_cfg)
      : teleop(load_teleop_file(kSrc + "/config/teleop/" + teleop_cfg), TeleopNode::Input::replay),
        mixer(kSrc + "/" + mixer_cfg),
        esc(kSrc + "/" + esc_cfg) {
    ex.add(esc);
    ex.add(mixer);
    ex.add(teleop);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kEscOutput) out.decode(d, 0, n);
      if (ch == channels::kArmState) arm.decode(d, 0, n);
    });
    js.device = "recorded";
    js.connected = true;
    js.n_axes = 6;
    js.axes = {0, 0, 0, 32767, 0, 0};
    js.n_buttons = 12;
    js.buttons.assign(12, false);
  }
  // Holds the stick state for `ms` milliseconds (a recorded stream sends it every 10 ms).
  void hold(int ms) {
    for (int i = 0; i < ms / 10; ++i) {
      t += 10'000;
      js.utime = t;
      ex.inject(channels::kJoystick, js, t);
      ex.run_until(t);
    }
  }
  void press(int button) {
    js.buttons[static_cast<std::size_t>(button)] = true;
    hold(100);
    js.buttons[static_cast<std::size_t>(button)] = false;
    hold(100);
  }
  void centre() {
    js.axes = {0, 0, 0, 32767, 0, 0};
    std::fill(js.buttons.begin(), js.buttons.end(), false);
  }
  // Normalised output per thruster name.
  std::map<std::string, double> u() const {
    std::map<std::string, double> m;
    for (int i = 0; i < out.n_channels; ++i)
      m[out.names[static_cast<std::size_t>(i)]] = out.normalized[static_cast<std::size_t>(i)];
    return m;
  }
  int value(const std::string& name) const {
    for (int i = 0; i < out.n_channels; ++i) {
      if (out.names[static_cast<std::size_t>(i)] == name)
        return out.value[static_cast<std::size_t>(i)];
    }
    return -1;
  }

  LockstepExecutor ex{0};
  TeleopNode teleop;
  MixerNode mixer;
  EscNode esc;
  joystick_state_t js;
  esc_output_t out{};
  arm_state_t arm{};
  TimeUs t = 0;
};

// The sign of each thruster's output (+1, -1, 0 for |u| < tol) in the given order.
std::vector<int> signs(const std::map<std::string, double>& u,
                       const std::vector<std::string>& order, double tol = 0.02) {
  std::vector<int> s;
  for (const auto& n : order) {
    const double v = u.at(n);
    s.push_back(v > tol ? 1 : v < -tol ? -1 : 0);
  }
  return s;
}

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
      EXPECT_NEAR(f.value("t" + std::to_string(i + 1)), c.expected[static_cast<std::size_t>(i)], 1)
          << "stick " << c.x << "," << c.y << " thruster t" << i + 1;
    }
  }
  // Half forward: the demand is the shaped stick value (0.348123, see teleop_node_test), and
  // seed 000's second condition makes the throttle that fraction of full.
  f.js.axes[1] = -16384;
  f.hold(100);
  EXPECT_NEAR(f.value("t1"), 0.3481233 * F, 2);
  EXPECT_NEAR(f.value("t3"), -0.3481233 * F, 2);
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
