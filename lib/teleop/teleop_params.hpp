// Parameters of tiller-teleop (plain struct) and their strict YAML loader.
//
// A stick axis is read in js units (-32767..32767) and normalised to [-1, 1] (a "trigger" axis,
// which rests at -32767, to [0, 1]). Shaping per axis: deadzone with rescaling
//   s = (|x| - d) / (1 - d) for |x| > d, else 0      (continuous at the edge, 1 at full deflection)
//   y = (1 - e) s + e s^3                            (expo e in [0, 1])
//   out = sign * sign(x) * y * axis_gain * global_gain, summed per DOF and clamped to [-1, 1].
// DOFs are the body FRD wrench axes [X Y Z K M N] = [surge sway heave roll pitch yaw]; + is the
// FRD positive axis (forward, right, down, roll right, nose up, yaw clockwise). The pilot's
// conventions ("up on the stick", "elevate up", "yaw clockwise") become FRD signs here, in the
// config's `sign`, and nowhere else.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/time.hpp"

namespace tiller {

inline constexpr int kJsAxisMax = 32767;

struct TeleopAxis {
  int axis = 0;            // js axis number
  int dof = 0;             // 0..5 = X Y Z K M N
  double sign = 1.0;       // +1 or -1: raw direction -> FRD direction
  bool trigger = false;    // rests at -32767 (a gamepad trigger): normalised to [0, 1]
  double deadzone = 0.05;  // [0, 0.9] of the normalised range
  double expo = 0.0;       // [0, 1]
  double gain = 1.0;       // [0, 1]
};

// Two buttons driving one DOF: +gain while `plus` is held, -gain while `minus` is held.
struct TeleopButtonAxis {
  int dof = 0;
  int plus = -1;
  int minus = -1;
  double gain = 1.0;
};

struct TeleopButtons {
  int arm = -1, disarm = -1;
  int mode_open_loop = -1, mode_closed_loop = -1, mode_autonomous = -1;
  int toggle_translation = -1;
  int gain_up = -1, gain_down = -1;
  // Arm with takeover: take control from another station in control (docs/safety.md).
  int takeover = -1;
  // The ROV pilot modes (tiller-rov-control; docs/flying.md): mode_open_loop is their manual.
  int mode_stabilise = -1, mode_depth_hold = -1, mode_heading_hold = -1, mode_rate = -1,
      mode_surface = -1, mode_position_hold = -1;
};

enum class YawMode { rate, heading_hold, torque };

struct TeleopParams {
  // This operator station's id, carried by its arm requests and manual commands: the station
  // that armed is in control and another station's commands are refused (docs/safety.md).
  // Empty in the file: tiller-teleop uses the host name.
  std::string station;
  // The node's name (heartbeat TILLER_HEARTBEAT_<NAME>, the signer's sender name): a second
  // teleop on one network needs its own (tiller-teleop --name), so its signed streams are its own.
  std::string node_name = "teleop";
  std::string device_path;         // e.g. /dev/input/js0, a FIFO or a file; empty: find by name
  std::string device_name;         // substring of JSIOCGNAME, used when device_path is empty
  TimeUs period = 20'000;          // fixed output rate (default 50 Hz)
  TimeUs reopen_period = 200'000;  // how often to look for an absent device
  bool publish_on_change = true;   // also publish the demand at once on new stick input
  std::vector<TeleopAxis> axes;
  std::vector<TeleopButtonAxis> button_axes;
  TeleopButtons buttons;
  TimeUs debounce = 30'000;  // a button change counts once stable this long
  double gain_initial = 1.0, gain_step = 0.25, gain_min = 0.25, gain_max = 1.0;
  // gain.wrap: a step past gain_max goes to gain_min (and below gain_min to gain_max), so one
  // button (gain_up alone) cycles the gain on a stick with no button to spare.
  bool gain_wrap = false;
  // Closed-loop manual (seed 004's manual cmd_vel / cmd_torque), full stick = these.
  std::array<double, 3> max_speed{0.5, 0.5, 0.3};  // [u v w] m/s
  double max_yaw_rate = 0.5;                       // rad/s
  double max_yaw_torque = 10.0;                    // N m
  YawMode yaw_mode = YawMode::heading_hold;
  TimeUs odometry_timeout = 500'000;
  std::int8_t initial_mode = 0;  // controller_mode_t constant
  bool initial_translation = false;
  // TILLER_MODE is published on the first tick (the initial mode), on every change, and repeated
  // every mode_repeat (0: never repeated), so a controller started after the teleop learns the
  // pilot's mode. While a teleop runs, the pilot's mode is the mode.
  TimeUs mode_repeat = 1'000'000;
};

// Reads the `teleop:` document root. Throws config::Error naming file, key and expectation.
TeleopParams load_teleop(const config::Value& root);
TeleopParams load_teleop_file(const std::string& path);

// DOF name ("surge"/"x", "sway"/"y", "heave"/"z", "roll"/"k", "pitch"/"m", "yaw"/"n") -> 0..5, or
// -1.
int dof_index(const std::string& name);

}  // namespace tiller
