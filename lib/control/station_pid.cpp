#include "control/station_pid.hpp"

#include <algorithm>
#include <cmath>

namespace tiller::control {

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
  double epsi = angle_diff(in.target_heading, in.heading);
  const bool integrate = in.dt > 0 && in.dt <= p_.max_dt;

  // Integral: body-frame increments, stored as a world-frame force.
  if (integrate) {
    const double dix = in.freeze[0] ? 0.0 : p_.x.ki * ex * in.dt;
    const double diy = in.freeze[1] ? 0.0 : p_.y.ki * ey * in.dt;
    i_world_[0] += c * dix - s * diy;
    i_world_[1] += s * dix + c * diy;
    if (!in.freeze[2])
      i_yaw_ = std::clamp(i_yaw_ + p_.yaw.ki * epsi * in.dt, -p_.yaw.i_limit, p_.yaw.i_limit);
  }
  double ix = c * i_world_[0] + s * i_world_[1];
  double iy = -s * i_world_[0] + c * i_world_[1];
  ix = std::clamp(ix, -p_.x.i_limit, p_.x.i_limit);
  iy = std::clamp(iy, -p_.y.i_limit, p_.y.i_limit);
  i_world_ = {c * ix - s * iy, s * ix + c * iy};  // keep the stored value within the bounds

  t.setpoint = {0.0, 0.0, wrap_pi(in.target_heading)};
  t.measured = {-ex, -ey, in.heading};  // body position relative to the target
  t.p = {p_.x.kp * ex, p_.y.kp * ey, 0};
  t.i = {ix, iy, i_yaw_};
  t.d = {-p_.x.kd * in.u, -p_.y.kd * in.v, -p_.yaw.kd * in.r};
  t.frozen = in.freeze;

  if (p_.weathervane) {
    // Demanded force in the world frame, produced by surge and heading alone.
    const double fx = t.p[0] + t.i[0] + t.d[0];
    const double fy = t.p[1] + t.i[1] + t.d[1];
    const double fn = c * fx - s * fy, fe = s * fx + c * fy;
    const double fmag = std::hypot(fn, fe);
    if (fmag > p_.weathervane_min_force) {
      double bearing = std::atan2(fe, fn);
      const double dist = std::hypot(en, ee);
      if (dist < p_.reverse_radius && std::abs(angle_diff(bearing, in.heading)) > kPi / 2) {
        bearing = wrap_pi(bearing + kPi);  // push astern instead of turning around
      }
      epsi = angle_diff(bearing, in.heading);
      t.setpoint[2] = bearing;
    }
    // Only the part of F along the bow can be produced.
    t.p[0] = p_.x.kp * ex;
    t.p[1] = 0;
    t.i[1] = 0;
    t.d[1] = 0;
    const double along = fn * c + fe * s;
    t.out[0] = std::clamp(along, -p_.x.max_output, p_.x.max_output);
    t.out[1] = 0;
  } else {
    t.out[0] = std::clamp(t.p[0] + t.i[0] + t.d[0], -p_.x.max_output, p_.x.max_output);
    t.out[1] = std::clamp(t.p[1] + t.i[1] + t.d[1], -p_.y.max_output, p_.y.max_output);
  }
  t.p[2] = p_.yaw.kp * epsi;
  t.out[2] = std::clamp(t.p[2] + t.i[2] + t.d[2], -p_.yaw.max_output, p_.yaw.max_output);
  return t;
}

}  // namespace tiller::control
