// The ROV pilot modes' buttons in the teleop presets (docs/flying.md, "ROV modes", has the
// table): each mode button of each preset publishes its controller_mode_t on TILLER_MODE, the
// 6-thruster and BlueROV2-class Extreme 3D Pro presets included position hold (head 4), and
// their one gain button (head 3) cycles the gain (gain.wrap). The 4-thruster ROV's preset has
// only manual and heading hold: the other modes need heave, roll or pitch (refused by
// tiller-rov-control on that layout).
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "teleop_rig.hpp"

namespace tiller {
namespace {

using test::config_path;
using test::Rig;
using M = controller_mode_t;

constexpr TimeUs ms(double v) {
  return static_cast<TimeUs>(v * 1000);
}

struct Press {
  Rig& r;
  joystick_state_t& s;
  double t = 100;
  void operator()(int b) {
    s.buttons[static_cast<std::size_t>(b)] = true;
    r.feed(ms(t));
    s.buttons[static_cast<std::size_t>(b)] = false;
    r.feed(ms(t + 50));
    t += 100;
  }
};

// The modes each preset's buttons publish, in the order pressed.
std::vector<std::int8_t> modes_from(const char* preset, const std::vector<int>& buttons) {
  TeleopParams p = load_teleop_file(config_path(preset));
  p.debounce = 0;
  Rig r(p);
  auto& s = r.plug_in();
  r.feed(ms(0));
  Press press{r, s};
  for (int b : buttons) press(b);
  std::vector<std::int8_t> out;
  for (const auto& [t, m] : r.all<controller_mode_t>(channels::kMode))
    if (t > 0) out.push_back(m.mode);
  return out;
}

TEST(RovPresets, EveryModeHasAButton) {
  // Extreme 3D Pro, 6-thruster and BlueROV2-class: base 9 manual, base 10 stabilise, base 11
  // depth hold, base 12 heading hold, base 8 surface, trigger rate, head 4 position hold.
  const std::vector<int> extreme = {9, 10, 11, 7, 0, 3, 8};
  const std::vector<std::int8_t> want = {M::STABILISE,       M::DEPTH_HOLD, M::HEADING_HOLD,
                                         M::SURFACE,         M::RATE,       M::POSITION_HOLD,
                                         M::MANUAL_OPEN_LOOP};
  EXPECT_EQ(modes_from("extreme3dpro_seed001.yaml", extreme), want);
  EXPECT_EQ(modes_from("extreme3dpro_bluerov2.yaml", extreme), want);
  // Gamepad: X stabilise, Y depth hold, Back heading hold, Guide surface, right-stick click
  // rate, left-stick click position hold, A manual.
  EXPECT_EQ(modes_from("gamepad_xbox.yaml", {2, 3, 6, 8, 10, 9, 0}), want);
  // The 4-thruster ROV: base 8 heading hold, base 9 manual.
  EXPECT_EQ(modes_from("extreme3dpro_seed000.yaml", {7, 8}),
            (std::vector<std::int8_t>{M::HEADING_HOLD, M::MANUAL_OPEN_LOOP}));
}

TEST(RovPresets, TheOneGainButtonCycles) {
  for (const char* preset : {"extreme3dpro_seed001.yaml", "extreme3dpro_bluerov2.yaml"}) {
    TeleopParams p = load_teleop_file(config_path(preset));
    p.debounce = 0;
    EXPECT_EQ(p.buttons.gain_down, -1) << preset;
    Rig r(p);
    auto& s = r.plug_in();
    r.feed(ms(0));
    Press press{r, s};
    std::vector<double> gains;
    for (int k = 0; k < 5; ++k) {
      press(2);
      gains.push_back(r.node.gain());
    }
    EXPECT_EQ(gains, (std::vector<double>{0.25, 0.5, 0.75, 1.0, 0.25})) << preset;
  }
}

}  // namespace
}  // namespace tiller
