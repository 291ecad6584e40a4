// Rig for flying a vehicle from joystick presets in one process on simulated time: TeleopNode
// (replay input: TILLER_JOYSTICK injected as a recorded stick would give it, every 10 ms) ->
// MixerNode -> EscNode (sim backend), in a LockstepExecutor. More nodes (e.g. a SimNode) can be
// added to `ex`. Used by fly_lockstep_test.cpp and fly_sim_rov_test.cpp.
#pragma once

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/joystick_state_t.hpp>

#include "esc/esc_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller::e2e {

inline const std::string kSrc = TILLER_SOURCE_DIR;

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
inline std::vector<int> signs(const std::map<std::string, double>& u,
                              const std::vector<std::string>& order, double tol = 0.02) {
  std::vector<int> s;
  for (const auto& n : order) {
    const double v = u.at(n);
    s.push_back(v > tol ? 1 : v < -tol ? -1 : 0);
  }
  return s;
}

}  // namespace tiller::e2e
