// A corner flown along a circular arc (a fillet): the arc of radius R tangent to both legs,
// from T1 = corner - t1 L on the incoming leg to T2 = corner + t2 L on the outgoing one, with
// L = R tan(d / 2) (d the turn angle) and the centre R along the normal to the inside of the turn.
// It passes R (1 / cos(d / 2) - 1) inside the corner. World frame: local NED [north east] m.
// The path follower flies it at the turn's speed U with the course turning at U / R (a course-rate
// feed-forward the follower hands the heading loop as a heading lead), the cross-track to the arc
// corrected as on a leg (docs/algorithms.md, "Corners in a current").
#pragma once

#include <Eigen/Core>

namespace tiller::guidance {

struct TurnArc {
  Eigen::Vector2d centre{0, 0};
  Eigen::Vector2d start{0, 0}, end{0, 0};  // T1, T2
  Eigen::Vector2d t2{1, 0};                // the outgoing leg's direction
  double radius = 0;                       // m
  double lead = 0;                         // m: L, from T1 to the corner (and corner to T2)
  double sign = 1;                         // +1: a right (clockwise) turn, -1: left
  bool valid = false;                      // false: no turn (straight on, or a hairpin)
};

// The fillet of radius `radius` at `corner` between unit directions t1 (in) and t2 (out); not
// valid for a turn below 1 mrad or above 120 deg (a hairpin: its arc would lie far from both
// legs' ends; the follower turns there as without an arc).
TurnArc make_turn_arc(const Eigen::Vector2d& corner, const Eigen::Vector2d& t1,
                      const Eigen::Vector2d& t2, double radius);

// Where the vehicle at `pos` is relative to the arc: the signed distance outside it (m, + away
// from the centre), the direction of travel along the arc there (unit), and whether it is past
// the arc's end (on the outgoing leg's side of the normal through T2).
struct ArcPosition {
  double outside = 0;
  Eigen::Vector2d tangent{1, 0};
  Eigen::Vector2d inward{0, 0};  // unit, toward the centre
  bool past_end = false;
};
ArcPosition locate(const TurnArc& arc, const Eigen::Vector2d& pos);

}  // namespace tiller::guidance
