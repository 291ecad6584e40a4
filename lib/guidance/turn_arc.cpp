#include "guidance/turn_arc.hpp"

#include <algorithm>
#include <cmath>

#include "core/angles.hpp"

namespace tiller::guidance {

TurnArc make_turn_arc(const Eigen::Vector2d& corner, const Eigen::Vector2d& t1,
                      const Eigen::Vector2d& t2, double radius) {
  TurnArc a;
  const double angle = std::acos(std::clamp(t1.dot(t2), -1.0, 1.0));
  if (!(radius > 0) || angle < 1e-3 || angle > 2 * kPi / 3) return a;
  a.sign = t1.x() * t2.y() - t1.y() * t2.x() > 0 ? 1.0 : -1.0;                // NED: + clockwise
  const Eigen::Vector2d inside1 = a.sign * Eigen::Vector2d(-t1.y(), t1.x());  // right normal * sign
  a.radius = radius;
  a.lead = radius * std::tan(angle / 2);
  a.start = corner - t1 * a.lead;
  a.end = corner + t2 * a.lead;
  a.centre = a.start + inside1 * radius;
  a.t2 = t2;
  a.valid = true;
  return a;
}

ArcPosition locate(const TurnArc& arc, const Eigen::Vector2d& pos) {
  ArcPosition p;
  const Eigen::Vector2d rho = pos - arc.centre;
  const double d = rho.norm();
  p.outside = d - arc.radius;
  p.inward = d > 1e-9 ? Eigen::Vector2d(-rho / d) : Eigen::Vector2d(0, 0);
  // Travel is clockwise (sign +1) about the centre: the tangent is the inward vector turned
  // 90 deg anticlockwise in NED for a right turn.
  p.tangent =
      d > 1e-9 ? Eigen::Vector2d(arc.sign * Eigen::Vector2d(p.inward.y(), -p.inward.x())) : arc.t2;
  p.past_end = arc.t2.dot(pos - arc.end) >= 0;
  return p;
}

WaterTurn plan_water_turn(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2,
                          const Eigen::Vector2d& current, double speed, double rate) {
  WaterTurn w;
  const double angle = std::acos(std::clamp(t1.dot(t2), -1.0, 1.0));
  if (!(rate > 0) || !(speed > 0) || !current.allFinite() || angle < 1e-3 || angle > 2 * kPi / 3)
    return w;
  w.ground1 = std::max(kWaterTurnMinGroundSpeed, speed + current.dot(t1));
  w.ground2 = std::max(kWaterTurnMinGroundSpeed, speed + current.dot(t2));
  const Eigen::Vector2d w1 = w.ground1 * t1 - current, w2 = w.ground2 * t2 - current;
  w.mag1 = w1.norm();
  w.mag2 = w2.norm();
  if (w.mag1 < 0.05 || w.mag2 < 0.05) return w;
  w.current = current;
  w.psi1 = std::atan2(w1.y(), w1.x());
  w.dpsi = angle_diff(std::atan2(w2.y(), w2.x()), w.psi1);
  w.duration = std::abs(w.dpsi) / rate;
  w.valid = true;
  w.displacement = ground_offset(w, w.duration);
  // Start at corner - t1 L, end on the outgoing line: n2 . (D - t1 L) = 0.
  const Eigen::Vector2d n2(-t2.y(), t2.x());
  const double across = n2.dot(t1);  // sin(angle), signed
  w.lead = std::max(0.1, n2.dot(w.displacement) / across);
  return w;
}

Eigen::Vector2d water_velocity(const WaterTurn& w, double tau) {
  if (!w.valid) return {0, 0};
  const double f = w.duration > 0 ? std::clamp(tau / w.duration, 0.0, 1.0) : 1.0;
  const double psi = w.psi1 + w.dpsi * f;
  return (w.mag1 + (w.mag2 - w.mag1) * f) * Eigen::Vector2d(std::cos(psi), std::sin(psi));
}

Eigen::Vector2d ground_offset(const WaterTurn& w, double tau) {
  Eigen::Vector2d d(0, 0);
  if (!w.valid) return d;
  tau = std::clamp(tau, 0.0, w.duration);
  const double h = tau / kWaterTurnSteps;
  for (int k = 0; k < kWaterTurnSteps; ++k) d += (water_velocity(w, (k + 0.5) * h) + w.current) * h;
  return d;
}

}  // namespace tiller::guidance
