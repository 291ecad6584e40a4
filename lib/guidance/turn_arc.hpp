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

// A corner flown through the water (turn_arc_frame: water): an underactuated boat cannot push
// sideways, so its heading points along its velocity through the water w = (ground velocity) - c,
// c the current, and it turns at its own rate. At `speed` through the water along each leg (over
// ground speed + c . t, at least kWaterTurnMinGroundSpeed), w turns from w1 = U1 t1 - c to
// w2 = U2 t2 - c (U the legs' ground speeds) at `rate` rad/s (the shorter way round), its
// magnitude linear in time from |w1| to |w2|; the ground track is its integral plus c t (the arc
// the hull flies in the water, carried by the current). World frame: local NED [north east] m,
// m/s. Not valid for a turn below 1 mrad or above 120 deg, without a rate, or with |w1| or |w2|
// below 0.05 m/s.
struct WaterTurn {
  Eigen::Vector2d current{0, 0};       // m/s NED, held through the turn
  double psi1 = 0;                     // rad NED: w1's direction
  double dpsi = 0;                     // rad, signed (+ clockwise): w2's direction - w1's
  double mag1 = 0, mag2 = 0;           // m/s: |w1|, |w2|
  double ground1 = 0, ground2 = 0;     // m/s: U1, U2 (over ground along the legs)
  double duration = 0;                 // s: |dpsi| / rate
  Eigen::Vector2d displacement{0, 0};  // m over ground from the turn's start to its end
  double lead = 0;  // m: where it starts, before the corner along t1, so that it ends on the
                    // outgoing leg's line (at least 0.1 m: in the segment, before the corner)
  bool valid = false;
};

WaterTurn plan_water_turn(const Eigen::Vector2d& t1, const Eigen::Vector2d& t2,
                          const Eigen::Vector2d& current, double speed, double rate);
// The velocity through the water `tau` s into the turn (clamped to [0, duration]), m/s NED.
Eigen::Vector2d water_velocity(const WaterTurn& w, double tau);
// The ground track's offset from the turn's start `tau` s into it (clamped), m: the integral of
// water_velocity + current (kWaterTurnSteps midpoint steps over [0, tau]; allocates nothing).
Eigen::Vector2d ground_offset(const WaterTurn& w, double tau);
inline constexpr int kWaterTurnSteps = 48;
inline constexpr double kWaterTurnMinGroundSpeed = 0.1;  // m/s

}  // namespace tiller::guidance
