// The velocity PID of seed 004 (velocity_pid_node): per axis surge, sway, yaw rate,
//   output = drag feed-forward (k_drag * sp + k_drag_quad * sp|sp|) + k_error * (sp - meas)
//            + integral of ki * (sp - meas) dt,
// body frame FRD: surge/sway setpoints and measurements in m/s, outputs X, Y in N; the yaw
// axis tracks a yaw rate (rad/s) and outputs N in N m. A heading target (rad NED) becomes a
// yaw-rate setpoint heading_kp * heading error, bounded by max_yaw_rate (a P outer loop), so
// every axis is the same drag + error + integral law. YAW_TORQUE passes a torque through.
//
// dt comes from the caller (the times of the measurements), never a fixed step: dt <= 0 or
// dt > max_dt does not integrate. The integral of an axis is frozen while `freeze` says the
// mixer reduced that axis (saturation, or no authority), and is bounded by i_limit (N or N m).
// Outputs are clamped to max_output. Non-finite inputs give a zero output and leave the state
// untouched. step() allocates nothing.
//
// Munk-moment cancellation (MunkModel, off unless configured; docs/algorithms.md, "Heading on
// a course-unstable hull"): a hull whose sway added mass exceeds its surge mass (m22 > m11, the
// Otter) turns sideways to the flow under the Munk moment (m22 - m11) u v, which grows with
// speed until the yaw-rate loop can no longer hold it (a sustained oscillation above 1.8 m/s on
// the Otter). The hull's sway equation m22 dv/dt + m23 dr/dt + y_v v + m11 u r = 0, driven by
// the measured surge speed u and yaw rate r, predicts the sway velocity through the water v_hat
// that the turning makes (no sway measurement, so a current's drift does not enter), and the
// yaw output adds fraction * (m22 - m11) u v_hat: the hull's own moment, cancelled. The term is
// part of the yaw feed-forward (PidTerms::ff) in the heading and rate modes; not in the torque
// mode.
#pragma once

#include <array>

#include "core/angles.hpp"

namespace tiller::control {

struct AxisGains {
  double k_drag = 0;        // N per (m/s) [N m per (rad/s)]: feed-forward on the setpoint
  double k_drag_quad = 0;   // N per (m/s)^2: quadratic feed-forward on the setpoint
  double k_error = 0;       // N per (m/s) of error
  double ki = 0;            // N per (m/s * s) of error
  double i_limit = 0;       // N: bound of the integral term
  double max_output = 1e5;  // N: bound of the axis output
};

// The hull's surge-sway-yaw numbers the Munk-moment cancellation uses (from its vehicle file,
// [u v r] with added mass). y_v = 0: off.
struct MunkModel {
  double m11 = 0;       // kg: surge mass, as in the hull's Coriolis matrix
  double m22 = 0;       // kg: sway mass
  double m23 = 0;       // kg m: sway-yaw coupling
  double y_v = 0;       // N s/m: linear sway damping
  double fraction = 1;  // of the moment cancelled
  bool enabled() const { return y_v > 0 && m22 > 0; }
};

struct VelocityPidParams {
  AxisGains surge, sway, yaw;  // yaw: on yaw rate, outputs N m
  MunkModel munk;
  double heading_kp = 1.0;    // (rad/s) per rad of heading error
  double max_yaw_rate = 0.5;  // rad/s
  double max_dt = 0.5;        // s: longer gaps do not integrate
};

enum class YawMode { kHeading, kRate, kTorque };

struct VelocityPidInput {
  double u_sp = 0, v_sp = 0;  // m/s body setpoint
  YawMode yaw_mode = YawMode::kRate;
  double yaw_value = 0;        // heading rad NED, rate rad/s or torque N m per yaw_mode
  double u = 0, v = 0, r = 0;  // measured body velocity m/s, rad/s
  double heading = 0;          // measured heading rad NED
  double dt = 0;               // s since the previous step
  std::array<bool, 3> freeze{false, false, false};  // mixer reduced [X Y N]
};

// One controller's internals per axis (what pid_terms_t carries).
struct PidTerms {
  std::array<double, 3> setpoint{}, measured{}, p{}, i{}, d{}, ff{}, out{};
  std::array<bool, 3> frozen{};
};

class VelocityPid {
 public:
  explicit VelocityPid(const VelocityPidParams& p = {}) : p_(p) {}
  PidTerms step(const VelocityPidInput& in);
  // Integrals and the sway prediction to zero.
  void reset() {
    integral_ = {0, 0, 0};
    sway_momentum_ = 0;
  }
  const std::array<double, 3>& integral() const { return integral_; }
  const VelocityPidParams& params() const { return p_; }

 private:
  VelocityPidParams p_;
  std::array<double, 3> integral_{0, 0, 0};  // N, N, N m (already multiplied by ki)
  double sway_momentum_ = 0;                 // m22 v_hat + m23 r, kg m/s (Munk model)
  double munk_moment(double u, double r, double dt);
};

}  // namespace tiller::control
