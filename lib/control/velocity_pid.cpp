#include "control/velocity_pid.hpp"

#include <algorithm>
#include <cmath>

namespace tiller::control {

// The yaw moment that cancels the hull's Munk moment now, then the sway prediction one step on
// (explicit Euler of the sway equation; its time constant m22 / y_v is 1 s for the Otter, 20
// steps at 20 Hz).
double VelocityPid::munk_moment(double u, double r, double dt) {
  const MunkModel& m = p_.munk;
  if (!m.enabled()) return 0;
  const double v_hat = (sway_momentum_ - m.m23 * r) / m.m22;
  if (dt > 0 && dt <= p_.max_dt) sway_momentum_ += dt * (-m.y_v * v_hat - m.m11 * u * r);
  return m.fraction * (m.m22 - m.m11) * u * v_hat;
}

PidTerms VelocityPid::step(const VelocityPidInput& in) {
  PidTerms t;
  const double vals[] = {in.u_sp, in.v_sp, in.yaw_value, in.u, in.v, in.r, in.heading, in.dt};
  for (double x : vals) {
    if (!std::isfinite(x)) return t;  // zero output, state untouched
  }
  const AxisGains* g[3] = {&p_.surge, &p_.sway, &p_.yaw};
  double r_sp = 0;
  switch (in.yaw_mode) {
    case YawMode::kHeading: {
      const double err = angle_diff(in.yaw_value, in.heading);
      r_sp = std::clamp(p_.heading_kp * err, -p_.max_yaw_rate, p_.max_yaw_rate);
      break;
    }
    case YawMode::kRate:
      r_sp = std::clamp(in.yaw_value, -p_.max_yaw_rate, p_.max_yaw_rate);
      break;
    case YawMode::kTorque:
      r_sp = 0;
      break;
  }
  const double sp[3] = {in.u_sp, in.v_sp, r_sp};
  const double meas[3] = {in.u, in.v, in.r};
  const bool integrate = in.dt > 0 && in.dt <= p_.max_dt;
  const double munk = munk_moment(in.u, in.r, in.dt);
  for (int k = 0; k < 3; ++k) {
    const AxisGains& a = *g[k];
    const double e = sp[k] - meas[k];
    t.setpoint[k] = sp[k];
    t.measured[k] = meas[k];
    t.frozen[k] = in.freeze[static_cast<std::size_t>(k)];
    if (k == 2 && in.yaw_mode == YawMode::kTorque) {
      integral_[2] = 0;
      t.ff[2] = in.yaw_value;
      t.out[2] = std::clamp(in.yaw_value, -a.max_output, a.max_output);
      continue;
    }
    if (integrate && !t.frozen[k]) {
      integral_[k] = std::clamp(integral_[k] + a.ki * e * in.dt, -a.i_limit, a.i_limit);
    }
    t.ff[k] = a.k_drag * sp[k] + a.k_drag_quad * sp[k] * std::abs(sp[k]) + (k == 2 ? munk : 0.0);
    t.p[k] = a.k_error * e;
    t.i[k] = integral_[k];
    t.out[k] = std::clamp(t.ff[k] + t.p[k] + t.i[k], -a.max_output, a.max_output);
  }
  if (in.yaw_mode == YawMode::kHeading) {
    t.setpoint[2] = wrap_pi(in.yaw_value);  // pid_terms_t: heading in the yaw slot
    t.measured[2] = in.heading;
  }
  return t;
}

}  // namespace tiller::control
