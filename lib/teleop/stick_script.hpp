// tiller-stick-script's logic: a scripted pilot. It holds a joystick (js units, -32767..32767
// per axis, buttons) through a list of steps, as a pilot watching the depth gauge and the compass
// would: each step holds some axes and presses some buttons, and ends after a time or once the
// vehicle has reached a depth or turned by an angle (from TILLER_ODOMETRY: depth = NED z, m,
// down positive; heading = yaw, rad). The app writes the stick as Linux js_event records into
// the FIFO that tiller-teleop reads as its device, so the demand takes the real joystick path:
// the teleop's centring, arming, deadzone and mode buttons all apply, nothing is bypassed.
// A step may measure: the depth error against a depth (m) and the heading error against the
// start heading plus an angle, or either against the value held when the measurement begins
// (`held`: what a depth-hold or heading-hold mode should keep), after a settling time; RMS and
// largest, checked against limits at the end (report()). Each step's start is printed on
// stderr ("tiller-stick-script: step 3/9: dive"), so a harness can act at a step. Pure: no
// device, no clock (time is what the executor tells). A step whose end condition is not met by
// its timeout, or odometry lost (older than the timeout, or without a valid depth and attitude
// in odometry_t.valid: not taken, counted in odometry.invalid) while a step needs it, fails the
// script: the stick is centred and the script stops.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <tiller/joystick_state_t.hpp>
#include <tiller/odometry_t.hpp>

#include "core/config.hpp"
#include "core/time.hpp"
#include "runtime/node.hpp"

namespace tiller {

struct StickStep {
  enum class Until { time, depth_at_least, depth_at_most, turned_at_least };
  std::string name;
  std::vector<std::pair<int, int>> axes;  // (axis, js value) held through the step; others 0
  std::vector<int> press;                 // buttons pressed for press_s at the step's start
  TimeUs hold = 0;                        // the step lasts at least this long
  Until until = Until::time;
  double until_value = 0;  // m (depth), rad (turn from the start heading, signed: + clockwise)
  TimeUs timeout = 60'000'000;
  // Measurement over the step, from `settle` after its start. NaN: not measured.
  double depth_m = std::numeric_limits<double>::quiet_NaN();
  double turn_rad = std::numeric_limits<double>::quiet_NaN();  // heading = start + turn
  bool depth_held = false, heading_held = false;  // against the value at the first sample
  TimeUs settle = 0;
  double max_depth_rms_m = std::numeric_limits<double>::infinity();
  double max_heading_rms_rad = std::numeric_limits<double>::infinity();
  double max_depth_m = std::numeric_limits<double>::infinity();      // largest |error| allowed
  double max_heading_rad = std::numeric_limits<double>::infinity();  // largest |error| allowed
  bool measured() const {
    return depth_held || heading_held || !std::isnan(depth_m) || !std::isnan(turn_rad);
  }
};

struct StickScriptParams {
  TimeUs period = 20'000;
  int n_axes = 6, n_buttons = 12;  // the stick the teleop preset expects (Extreme 3D Pro)
  TimeUs press = 200'000;          // how long a press holds a button down
  TimeUs odometry_timeout = 500'000;
  TimeUs start_timeout = 20'000'000;  // the first odometry must come within this
  std::vector<StickStep> steps;
};

// Reads the `stick_script:` keys of a file's root. Throws config::Error naming file and key.
StickScriptParams load_stick_script(const config::Value& root);
StickScriptParams load_stick_script_file(const std::string& path);

// One measured step's result.
struct StickMeasure {
  std::string step;
  int samples = 0;
  double depth_rms = 0, depth_max = 0;      // m, |error|
  double heading_rms = 0, heading_max = 0;  // rad, |error|
  double depth_ref = 0, heading_ref = 0;    // m, rad: what the errors are measured against
  bool depth = false, heading = false;      // what was measured
  bool passed = true;
};

class StickScriptNode : public Node {
 public:
  explicit StickScriptNode(StickScriptParams p);

  // Called with the whole stick whenever an axis or a button changes (and once at the start).
  void on_stick(std::function<void(const joystick_state_t&, TimeUs)> f) {
    on_stick_ = std::move(f);
  }
  bool done() const { return done_; }
  bool failed() const { return !why_.empty(); }
  const std::string& why() const { return why_; }
  const std::vector<StickMeasure>& measures() const { return measures_; }
  // Lines for the pilot's log: each measured step's errors, the verdict.
  std::string report() const;
  const joystick_state_t& stick() const { return js_; }
  int step() const { return step_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  void on_odometry(const odometry_t& o, TimeUs now);
  void start_step(int i, TimeUs now);
  void fail(const std::string& why, TimeUs now);
  void set_stick(TimeUs now);
  bool condition_met(const StickStep& s) const;

  StickScriptParams p_;
  std::function<void(const joystick_state_t&, TimeUs)> on_stick_;
  joystick_state_t js_;
  Freshness odom_fresh_;
  bool have_odom_ = false;
  double depth_ = 0, heading_ = 0, start_heading_ = 0, turned_ = 0;  // turned_: unwrapped
  double last_heading_ = 0;
  int step_ = -1;  // -1: waiting for odometry
  TimeUs step_start_ = 0, first_tick_ = -1;
  bool done_ = false;
  std::string why_;
  std::vector<StickMeasure> measures_;
  double sum_d2_ = 0, sum_h2_ = 0;
  std::int64_t *rejected_odom_, *invalid_odom_;
};

}  // namespace tiller
