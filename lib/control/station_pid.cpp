#include "control/station_pid.hpp"

#include <algorithm>
#include <cmath>

namespace tiller::control {

double StationPid::force_weight(double fmag) const {
  const double span = p_.weathervane_full_force - p_.weathervane_min_force;
  return span > 0 ? std::clamp((fmag - p_.weathervane_min_force) / span, 0.0, 1.0)
                  : (fmag > p_.weathervane_min_force ? 1.0 : 0.0);
}

PidTerms StationPid::step(const StationPidInput& in) {
  PidTerms t;
  const double vals[] = {
      in.target_n, in.target_e, in.target_heading, in.n, in.e, in.heading, in.u, in.v, in.r, in.dt};
  for (double x : vals) {
    if (!std::isfinite(x)) return t;
  }
  const double c = std::cos(in.heading), s = std::sin(in.heading);
  const double en = in.target_n - in.n, ee = in.target_e - in.e;
  const double ex = c * en + s * ee;
  const double ey = -s * en + c * ee;
  const double epsi_target = angle_diff(in.target_heading, in.heading);
  const bool integrate = in.dt > 0 && in.dt <= p_.max_dt;

  // Integral (x, y): body-frame increments, stored as a world-frame force. In weathervane mode
  // the whole force is made by surge with the bow turned along it, so the sideways part
  // integrates whenever surge does (the mixer's "sway unactuated" does not freeze it), and the
  // bound is on the magnitude (x.i_limit), which does not change as the boat turns. Before
  // (issue 13 finding 3) sway never integrated: after a turn the world-fixed integral had a
  // sideways part that could not unwind, and the heading loop settled where the sway P term
  // cancelled it, a standing offset I_y / kp_y (0.67 m) to the side.
  // The sideways part is produced only as far as the heading follows the force, so it integrates
  // with the weight the heading gives the force (0 below weathervane_min_force, where the target
  // heading is held: in still water a small sideways error inside that band would otherwise wind
  // the integral up until the boat turned across the target heading and wandered).
  const bool freeze_y = p_.weathervane ? in.freeze[0] : in.freeze[1];
  double y_weight = 1.0;
  if (p_.weathervane) {
    const double fx0 = p_.x.kp * ex - p_.x.kd * in.u + (c * i_world_[0] + s * i_world_[1]);
    const double fy0 = p_.y.kp * ey - p_.y.kd * in.v + (-s * i_world_[0] + c * i_world_[1]);
    y_weight = force_weight(std::hypot(fx0, fy0));
  }
  if (integrate) {
    const double dix = in.freeze[0] ? 0.0 : p_.x.ki * ex * in.dt;
    const double diy = freeze_y ? 0.0 : y_weight * p_.y.ki * ey * in.dt;
    i_world_[0] += c * dix - s * diy;
    i_world_[1] += s * dix + c * diy;
  }
  double ix = c * i_world_[0] + s * i_world_[1];
  double iy = -s * i_world_[0] + c * i_world_[1];
  if (p_.weathervane) {
    const double mag = std::hypot(ix, iy);
    if (mag > p_.x.i_limit) {
      ix *= p_.x.i_limit / mag;
      iy *= p_.x.i_limit / mag;
    }
  } else {
    ix = std::clamp(ix, -p_.x.i_limit, p_.x.i_limit);
    iy = std::clamp(iy, -p_.y.i_limit, p_.y.i_limit);
  }
  i_world_ = {c * ix - s * iy, s * ix + c * iy};  // keep the stored value within the bounds

  t.setpoint = {0.0, 0.0, wrap_pi(in.target_heading)};
  t.measured = {-ex, -ey, in.heading};  // body position relative to the target
  t.p = {p_.x.kp * ex, p_.y.kp * ey, 0};
  t.i = {ix, iy, 0};
  t.d = {-p_.x.kd * in.u, -p_.y.kd * in.v, -p_.yaw.kd * in.r};
  t.frozen = {in.freeze[0], freeze_y, in.freeze[2]};

  double epsi = epsi_target;
  if (p_.weathervane) {
    // Demanded force in the world frame, produced by surge and heading alone.
    const double fx = t.p[0] + t.i[0] + t.d[0];
    const double fy = t.p[1] + t.i[1] + t.d[1];
    const double fn = c * fx - s * fy, fe = s * fx + c * fy;
    const double fmag = std::hypot(fn, fe);
    // Heading error toward the force: the bow along it (d_bow), or, close to the target, the
    // hull's axis along it, bow or stern whichever is nearer (d_axis: 0 with the force dead
    // astern, so the boat pushes astern), faded to 0 at 90 deg off the bow, so that, unlike a
    // switch between bow and stern, it is continuous there. Between reverse_radius and
    // reverse_radius + reverse_blend the two fade into each other; and the whole fades in with
    // |F| between weathervane_min_force and weathervane_full_force (below: the target heading).
    // No switch anywhere: the yaw demand is continuous in the error.
    if (fmag > 0) {
      double d_bow = angle_diff(std::atan2(fe, fn), in.heading);
      // Hysteresis at the stern: a force crossing dead astern (more than 150 deg off the bow)
      // keeps the turn going the way it was instead of reversing full yaw.
      if (std::abs(d_bow) > 5 * kPi / 6 && turn_ != 0 && (d_bow > 0 ? 1 : -1) != turn_)
        d_bow += 2 * kPi * turn_;
      turn_ = d_bow > 0 ? 1 : d_bow < 0 ? -1 : turn_;
      // Toward the nearer end of the hull's axis (bow or stern), at full strength up to 60 deg
      // off the axis, fading to 0 at 90 deg (where bow and stern are equally near).
      const double d_end = std::abs(d_bow) <= kPi / 2 ? d_bow : wrap_pi(d_bow + kPi);
      const double d_axis = d_end * std::min(1.0, std::abs(std::cos(d_bow)) / std::cos(kPi / 3));
      const double dist = std::hypot(en, ee);
      const double w_bow = p_.reverse_blend > 0
                               ? std::clamp((dist - p_.reverse_radius) / p_.reverse_blend, 0.0, 1.0)
                               : (dist >= p_.reverse_radius ? 1.0 : 0.0);
      const double d_force = w_bow * d_bow + (1 - w_bow) * d_axis;
      const double w_force = force_weight(fmag);
      epsi = w_force * d_force + (1 - w_force) * epsi_target;
      t.setpoint[2] = wrap_pi(in.heading + epsi);
    }
    // The heading setpoint moves at most heading_rate_limit (a gap longer than max_dt, or the
    // first step, starts it afresh).
    if (p_.heading_rate_limit > 0) {
      const double step = p_.heading_rate_limit * in.dt;
      const double d = angle_diff(t.setpoint[2], last_setpoint_);
      if (have_setpoint_ && in.dt > 0 && in.dt <= p_.max_dt && std::abs(d) > step) {
        t.setpoint[2] = wrap_pi(last_setpoint_ + std::clamp(d, -step, step));
        epsi = angle_diff(t.setpoint[2], in.heading);
      }
      have_setpoint_ = true;
      last_setpoint_ = t.setpoint[2];
    }
    // Only the part of F along the bow can be produced: it is fx = P + I + D of the x axis.
    // The sway terms stay published as they are applied: their sum is the sideways part of F,
    // which the heading setpoint (setpoint[2]) turns the bow toward; no sway force is sent.
    t.out[0] = std::clamp(fn * c + fe * s, -p_.x.max_output, p_.x.max_output);
    t.out[1] = 0;
  } else {
    t.out[0] = std::clamp(t.p[0] + t.i[0] + t.d[0], -p_.x.max_output, p_.x.max_output);
    t.out[1] = std::clamp(t.p[1] + t.i[1] + t.d[1], -p_.y.max_output, p_.y.max_output);
  }
  // Yaw: P and I on the heading error in force (the target's, or the weathervane's), so the
  // published P + I + D is the output (up to max_output).
  if (integrate && !in.freeze[2]) {
    i_yaw_ = std::clamp(i_yaw_ + p_.yaw.ki * epsi * in.dt, -p_.yaw.i_limit, p_.yaw.i_limit);
  }
  t.i[2] = i_yaw_;
  t.p[2] = p_.yaw.kp * epsi;
  t.out[2] = std::clamp(t.p[2] + t.i[2] + t.d[2], -p_.yaw.max_output, p_.yaw.max_output);
  return t;
}

}  // namespace tiller::control
