// mission::PolygonPaths: shortest paths that stay inside a simple polygon (local NED m), for a
// survey's transits between its cells (mission/survey.hpp). The path's corners are the polygon's
// vertices moved `clearance_m` into the polygon along their bisectors (a shortest path inside a
// polygon bends only at its reflex vertices; the clearance keeps it off the shore); a segment is
// usable when it crosses no edge and its points are inside (mission/fence.hpp's inside test).
// The corners' visibility graph is built once (O(n^3) for n vertices); each query adds its two
// ends and runs Dijkstra. A planning tool's code: it allocates.
#pragma once

#include <vector>

#include "mission/mission.hpp"

namespace tiller::mission {

class PolygonPaths {
 public:
  PolygonPaths(const std::vector<MissionPoint>& polygon, double clearance_m);
  // The corners between a and b (both inside or on the boundary), not a and b themselves; empty
  // when the straight segment is usable. `length` (if given) gets the path's length in m, or
  // +inf when no path was found (then the result is empty too).
  std::vector<MissionPoint> via(const MissionPoint& a, const MissionPoint& b,
                                double* length = nullptr) const;
  // The straight segment a-b stays inside the polygon.
  bool visible(const MissionPoint& a, const MissionPoint& b) const;

 private:
  std::vector<MissionPoint> poly_;
  std::vector<MissionPoint> corners_;
  std::vector<std::vector<double>> dist_;  // corner to corner, +inf when not visible
};

}  // namespace tiller::mission
