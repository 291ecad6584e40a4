// A corner flown as a pivot (turn_pivot): the boat stops over ground at a pivot point S on the
// incoming leg, turns there in place to the outgoing leg's heading while it holds S, and only
// then sets off along the outgoing leg. World frame: local NED [north east] m, m/s, rad.
//
// Turning in place, surge cancels the current's part along the heading; only its part across the
// heading, which an underactuated hull cannot oppose, drifts the boat. S is set back from the
// corner along the incoming leg by that drift (pivot_drift) less an allowance, at most a maximum
// offset inside the acceptance radius. Measured in docs/corners.md.
//
// The drift: the heading h(theta) turns from t1 to t2 at rate r; n(theta) is its normal and o the
// outside of the turn (t1's part normal to t2, unit). The drift outward is
//   D = (1 / r) * integral over theta of (c . n(theta)) (n(theta) . o) dtheta,
// for a 90 deg turn (c1, c2 the current along t1, t2) D = (pi / 4 c1 - c2 / 2) / r: a following
// current on the incoming leg and a head current on the outgoing one push the boat out.
#pragma once

#include <Eigen/Core>

namespace tiller::guidance {

// The predicted drift across the outgoing leg (m, + to the outside of the turn) of a pivot from
// unit direction t1 to unit direction t2 (the shorter way round) at `rate` rad/s in current `c`
// m/s NED, the along-heading motion held. 0 without a rate or for a turn below 1 mrad.
// kPivotSteps midpoint steps; allocates nothing.
double pivot_drift(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2, const Eigen::Vector2d& c,
                   double rate);
inline constexpr int kPivotSteps = 32;

// Where the pivot point is set back from the corner along t1 (m, in [0, max_offset]): the drift
// less `allowance` (the overshoot accepted past the next leg's line).
double pivot_setback(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2, const Eigen::Vector2d& c,
                     double rate, double allowance, double max_offset);

}  // namespace tiller::guidance
