#include "guidance/pivot_turn.hpp"

#include <algorithm>
#include <cmath>

namespace tiller::guidance {

double pivot_drift(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2, const Eigen::Vector2d& c,
                   double rate) {
  const double cross = t1.x() * t2.y() - t1.y() * t2.x();  // + : t2 clockwise of t1 (NED)
  const double angle = std::atan2(std::abs(cross), t1.dot(t2));
  if (!(rate > 0) || angle < 1e-3 || !c.allFinite()) return 0;
  Eigen::Vector2d o = t1 - t2 * t1.dot(t2);
  if (o.norm() < 1e-9) return 0;  // a hairpin: no outside across the next leg
  o.normalize();
  const double sign = cross >= 0 ? 1.0 : -1.0;
  const double step = angle / kPivotSteps;
  const double psi1 = std::atan2(t1.y(), t1.x());
  double d = 0;
  for (int k = 0; k < kPivotSteps; ++k) {
    const double psi = psi1 + sign * (k + 0.5) * step;
    const Eigen::Vector2d n(-std::sin(psi), std::cos(psi));  // the heading's normal
    d += c.dot(n) * n.dot(o);
  }
  return d * step / rate;
}

double pivot_setback(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2, const Eigen::Vector2d& c,
                     double rate, double allowance, double max_offset) {
  return std::clamp(pivot_drift(t1, t2, c, rate) - allowance, 0.0, std::max(0.0, max_offset));
}

}  // namespace tiller::guidance
