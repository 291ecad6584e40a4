// control::RovAxes: the ROV's 6-DOF per-axis controller (tiller-rov-control). Each axis of the
// body wrench [X Y Z K M N] is independently one of
//   kOff    not controlled: 0 (an axis the layout cannot actuate, or a mode that leaves it)
//   kPilot  pilot pass-through: stick * pilot * the layout's largest force / moment that way
//   kRate   velocity or rate: PI on (stick * max_rate - measured rate)
//   kHold   hold a value; the pilot overrides it by moving the stick (the axis then tracks
//           stick * max_rate as kRate does), and on release (or on entering the role while
//           moving) it brakes: the rate setpoint ramps to 0 at max_accel (at once with
//           max_accel 0), and once it is 0 the value is held as soon as the rate is under
//           capture_rate (or capture_s has passed): the new depth, heading, attitude or
//           position, where the vehicle stopped (a value captured while still moving, or a
//           reference run ahead of a vehicle that lags it, would be passed and come back to).
//           While braking the integral moves only from its value at the brake's start toward
//           its value when the axis last held, not past it (rov_axes.cpp, brake_limited).
// A rate setpoint (kRate, a kHold override or its brake) moves toward its goal by at most
// max_accel per second (at once with 0), starting from the measured rate: no thrust step when
// a stick is pressed or released.
// What each axis measures (RovState, from TILLER_ODOMETRY):
//   X, Y  hold: the NED position [north east] (held together: either stick moved overrides
//         both), its error turned into the body frame by the heading, their integral kept in
//         NED; rate: body u, v (m/s)
//   Z     world vertical: hold the depth (NED down, m), rate: the depth rate (m/s, + down; stick
//         + = down, FRD); the law's force is along NED down and enters the wrench as R^T [0 0 F]
//   K, M  roll, pitch (rad; `level` holds 0 rather than the value at entry); rate: body p, q
//   N     heading (rad, wrapped); rate: body r (rad/s)
// A roll or pitch rate from the stick slows to 0 at max_angle (the setpoint is at most
// kp / kd times the angle left), so a held stick tilts the vehicle that far and no further.
// Law per controlled axis (out in N or N m, clamped to +-max_output):
//   holding     out = kp e - kd v + I,           I += ki e dt
//   rate/brake  out = kd (v_sp - v) + I,          I += ki_rate (v_sp - v) dt
// One integrator per axis, in N / N m, shared by both laws, so a pilot override and the
// capture after it are bumpless. |I| <= i_limit. Anti-windup: the integral does not grow
// further in the direction of an axis the mixer reports reduced (saturated) for this source,
// and follows the safety gate's rule (control/integrator_gate.hpp): kReset zeroes it and makes
// every hold target follow the vehicle (a start holds where the vehicle is), kFreeze keeps it.
// An axis that becomes kRate or kHold from kOff or kPilot starts from zero integral; one that
// leaves them forgets it. Pure: state, stick and dt in, wrench out; no allocation.
#pragma once

#include <array>
#include <cstdint>

#include "control/integrator_gate.hpp"

namespace tiller::control {

enum class AxisRole : std::int8_t { kOff, kPilot, kRate, kHold };

struct RovGains {
  double pilot = 1.0;       // [0, 1]: fraction of the layout's largest force at full stick
  double kp = 0;            // N/m or N m/rad
  double ki = 0;            // N/(m s) or N m/(rad s): integral of the hold error
  double kd = 0;            // N/(m/s) or N m/(rad/s): rate gain (hold damping, rate tracking)
  double ki_rate = 0;       // N/m or N m/rad: integral of the rate error
  double i_limit = 0;       // N or N m
  double max_output = 1e9;  // N or N m
  double max_rate = 0.5;    // m/s or rad/s at full stick
  double capture_rate = 0;  // m/s or rad/s: below this after a release the new value is held
  double capture_s = 1.5;   // s: held at the latest this long after a release
  double max_angle = 0;     // roll, pitch: rad; a stick's rate stops at this angle (0: none)
  double max_accel = 0;     // m/s^2 or rad/s^2: the rate setpoint's largest change (0: none)
};

// The vehicle's state as the controller sees it (odometry: NED pose, body FRD velocity).
struct RovState {
  double north = 0, east = 0, depth = 0;  // m, NED
  double roll = 0, pitch = 0, yaw = 0;    // rad, ZYX Euler
  std::array<double, 6> nu{};             // [u v w] m/s, [p q r] rad/s, body FRD
};

class RovAxes {
 public:
  RovAxes(const std::array<RovGains, 6>& gains, const std::array<double, 6>& max_plus,
          const std::array<double, 6>& max_minus);

  // Sets each axis' role; `level` makes a roll or pitch hold hold 0 (stabilise) instead of the
  // value it captures. Changes only the axes whose role changes (see above).
  void set_roles(const std::array<AxisRole, 6>& roles, bool level);
  // One step: stick in [-1, 1]^6 (FRD), dt seconds since the last step (0: no integration),
  // `reduced` the mixer's per-axis saturation flags for this source (false when unknown).
  // Returns the body wrench [X Y Z K M N].
  std::array<double, 6> step(const RovState& s, const std::array<double, 6>& stick, double dt,
                             IntegratorRule rule, const std::array<bool, 6>& reduced);

  AxisRole role(int axis) const { return ax_[static_cast<std::size_t>(axis)].role; }
  // True while an axis in kHold holds its target (not overridden, not braking).
  bool holding(int axis) const { return ax_[static_cast<std::size_t>(axis)].holding; }
  double target(int axis) const { return ax_[static_cast<std::size_t>(axis)].target; }
  // The rate setpoint in force (kRate, a kHold override or its brake).
  double setpoint(int axis) const { return ax_[static_cast<std::size_t>(axis)].sp; }
  double integral(int axis) const { return ax_[static_cast<std::size_t>(axis)].i; }
  // Guidance (waypointing): a kHold axis holds `target` from this step on (neither braking nor
  // overridden while its stick is 0), with `rate` (m/s or rad/s, the target's own rate of change)
  // as the hold law's rate setpoint: out = kp e + kd (rate - v) + I. X and Y take their targets
  // as NED north and east, their rates as NED rates. Other roles: ignored. The feed-forward lasts
  // one step.
  void guide(int axis, double target, double rate = 0);
  // The force along NED down the Z law asks for (N), before it is turned into the body frame.
  double vertical_force() const { return vertical_; }

 private:
  struct Axis {
    AxisRole role = AxisRole::kOff;
    bool holding = false;      // kHold: holding the target
    bool sp_set = false;       // sp has been started (from the measured rate)
    bool braking = false;      // kHold: braking after a release or an entry
    double i_hold = 0;         // the integral when the axis last held
    double i_brake = 0;        // the integral when the brake began
    double since_release = 0;  // s braking with the setpoint at 0
    double sp = 0;             // the rate setpoint in force (ramped at max_accel)
    double target = 0;
    double i = 0;
    double ff = 0;  // guide()'s rate for this step (0 otherwise)
  };
  // The axis' measured value (hold) and rate.
  static double value(int axis, const RovState& s);
  static double rate(int axis, const RovState& s);
  // target - the measured value (wrapped for the heading).
  static double error(int axis, const RovState& s, double target);
  // A roll or pitch rate setpoint limited by max_angle (others unchanged).
  double angle_limited(int a, double v_sp) const;
  // hold: kp e - kd v + I with I += ki e dt; else kd (v_sp - v) + I, I += ki_rate ...
  double law(int a, double e, double v_sp, double v, bool hold, double dt, IntegratorRule rule,
             bool reduced);
  void step_xy(const RovState& s, const std::array<double, 6>& stick, double dt,
               IntegratorRule rule, const std::array<bool, 6>& reduced, std::array<double, 6>& out);

  std::array<RovGains, 6> g_;
  std::array<double, 6> max_plus_, max_minus_;
  std::array<Axis, 6> ax_{};
  bool level_ = false;
  double vertical_ = 0;
  std::array<double, 2> angle_now_{};  // roll, pitch of the step's state
  std::array<double, 2> i_ne_{};       // X and Y holding position: their integral in NED (N)
  std::array<double, 2> i_ne_hold_{}, i_ne_brake_{};  // ... when last holding, at the brake
  bool xy_held_ = false;  // X and Y held together in the last step (i_ne_ is theirs)
};

}  // namespace tiller::control
