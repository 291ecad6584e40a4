// tiller-teleop's logic: joystick states in, pilot demands out. Pure: no device, no clock.
//
// Input: joystick_state_t (raw js-unit axes and buttons, plus whether the device is present),
// either fed by the app straight from the device (feed(), live mode: the node then publishes
// TILLER_JOYSTICK itself, for logs) or, for replay, taken from TILLER_JOYSTICK
// (Input::replay). Optional TILLER_ODOMETRY gives the heading for closed-loop heading hold;
// TILLER_ARM_STATE (from tiller-esc) is shown in the heartbeat status for the pilot: armed or
// not, the station in control and the vehicle's reason (a refusal: "another station in control:
// B", "stick not centred", ...), the heartbeat going out at once when they change. Its freshness
// is judged by arrival time, so a topside clock out of step with the vehicle's still shows the
// vehicle's state. Arm requests carry the latest arm state's boot nonce and params.station; the
// takeover button asks for control while another station holds it.
// A rise in joystick_state_t.late_inits (the device re-sent its start-up state after ordinary
// input) is treated as a reconnection: neutral and invalid at once, a disarm request, and the
// stick must be centred again (counted in joystick.reinit).
// Outputs, every period and at once when the stick moves (publish_on_change):
//   TILLER_MANUAL_DEMAND   normalised [X Y Z K M N] FRD in [-1, 1] (see teleop_params.hpp)
//   TILLER_MANUAL_VELOCITY body [u v w] m/s and yaw rate / heading / torque (seed 004)
// TILLER_ARM_REQUEST only on a (debounced) button press: an arm request is an event, never
// repeated, so a timeout that disarmed the ESCs is not undone behind the pilot's back.
// TILLER_MODE on the first tick (initial_mode), on a button press, and again every
// mode_repeat_hz (default 1 Hz) so a controller started later learns the pilot's mode. A
// TILLER_MODE from another source (a mode command: `tiller-rov-control --mode`, the cockpit)
// becomes the teleop's mode, so its repeats carry the command rather than undo it.
// Safety: a state with connected=false gives a neutral, invalid demand published at once and
// a DEGRADED "joystick absent" heartbeat. After (re)connection the output stays neutral and
// invalid until every mapped axis has been reported by the device and seen inside its deadzone
// (no jump to a held deflection; an axis never reported is not centred); buttons held at
// connection count only after they are released. shutdown() (SIGINT, SIGTERM) publishes a
// neutral, invalid demand. The mode_autonomous button also sends an operator RESUME on
// TILLER_MISSION_COMMAND (the autonomy's go, docs/safety.md).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/joystick_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/odometry_t.hpp>

#include "runtime/node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller {

// Shapes one normalised axis value x in [-1, 1]: deadzone with rescaling, then expo (no gain).
double shape_axis(double x, double deadzone, double expo);
// Normalises a raw js value: [-1, 1], or [0, 1] for a trigger axis.
double normalise_axis(int raw, bool trigger);

// How far a TILLER_ARM_STATE's stamp may be from this station's clock, either way, and still be
// shown: beyond the signing window (1 s by default) that already bounds a replay.
inline constexpr TimeUs kArmStateSkewUs = 2'000'000;

class TeleopNode : public Node {
 public:
  enum class Input { device, replay };
  explicit TeleopNode(TeleopParams params, Input input = Input::device);

  // Live mode: a new state read from the device (or a disconnection) at time `now`.
  void feed(const joystick_state_t& state, TimeUs now);
  // Publishes a neutral, invalid demand (the process is stopping).
  void shutdown(TimeUs now) override;
  // Device mode: the js_event records the device parser has dropped so far (unknown type, axis or
  // button number out of range), counted as rejected.js_event.bad. Returns true when it grew.
  bool note_bad_js_events(std::int64_t total);

  // For tests and the heartbeat.
  bool connected() const { return connected_; }
  bool centred() const { return centred_; }
  // The vehicle's latest arm state as this station sees it.
  bool arm_known() const { return arm_known_; }
  bool armed() const { return armed_; }
  const std::string& controller() const { return controller_; }
  const std::string& vehicle_reason() const { return vehicle_reason_; }
  double gain() const { return gain_; }
  std::int8_t mode() const { return mode_; }
  bool is_translation() const { return translation_; }
  const std::array<double, 6>& demand() const { return demand_; }
  const TeleopParams& params() const { return p_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  void on_joystick(const joystick_state_t& s, TimeUs now);
  void on_odometry(const odometry_t& o, TimeUs now);
  void on_arm_state(const arm_state_t& a, TimeUs now);
  void on_mode(const controller_mode_t& m, TimeUs now);
  void process(const joystick_state_t& s, TimeUs now);
  void apply_state(const joystick_state_t& s, TimeUs now);
  void update_buttons(TimeUs now);
  void on_press(int button, TimeUs now);
  bool compute_demand();  // from raw_*; returns true if the output changed
  void device_reinit(TimeUs now);
  void send_arm_request(bool arm, bool takeover, TimeUs now);
  void publish_outputs(TimeUs now);
  void publish_mode(TimeUs now);
  void update_health();

  TeleopParams p_;
  Input input_;
  std::string device_;
  bool connected_ = false;
  bool centred_ = false;
  std::vector<std::int16_t> raw_axes_;
  std::vector<bool> raw_buttons_;
  std::vector<bool> stable_;       // debounced button state
  std::vector<TimeUs> raw_since_;  // when the raw state last changed
  std::vector<bool> inhibited_;    // held at connection: ignore until released
  std::array<double, 6> demand_{};
  bool valid_ = false;
  double gain_;
  std::int8_t mode_;
  bool translation_;
  bool mode_sent_ = false;  // the first tick publishes the initial mode
  TimeUs last_mode_sent_ = 0;
  // heading hold
  Freshness odom_fresh_;
  double heading_ = 0.0;
  bool holding_ = false;
  double held_heading_ = 0.0;

  joystick_state_t js_msg_;
  manual_demand_t demand_msg_;
  manual_velocity_cmd_t velocity_msg_;
  std::int64_t* rejected_state_;
  std::int64_t* bad_js_events_;
  std::int64_t* rejected_odom_;
  std::int64_t* rejected_odom_range_ = nullptr;  // created on first use
  std::int64_t* disconnects_;
  std::int64_t* presses_;
  std::int64_t* bounces_;
  Freshness arm_fresh_{500'000};
  int arm_shown_ = -1;  // -1 unknown, 0 disarmed, 1 armed: what the status says
  bool armed_ = false;
  bool arm_known_ = false;       // a fresh TILLER_ARM_STATE
  std::int64_t boot_nonce_ = 0;  // the latest arm state's (arm requests carry it)
  std::string controller_;       // its station in control
  std::string vehicle_reason_;   // its reason
  std::int32_t late_inits_ = 0;  // the device's late INIT count at the last state
  std::int64_t* reinits_;
};

}  // namespace tiller
