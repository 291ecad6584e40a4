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

}  // namespace tiller::guidance
