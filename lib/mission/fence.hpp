// A mission's geofence (Mission::fence, local NED m): is a point allowed, and the checks a
// mission's items get at load. A point is allowed when it is inside every inclusion shape and
// outside every exclusion shape (ArduPilot's polygon and circle fences, as QGroundControl plans
// them: https://ardupilot.org/rover/docs/common-polygon_fence.html). A point on an edge counts as
// inside. Allocation free; no clock.
#pragma once

#include <string>
#include <vector>

#include "mission/mission.hpp"

namespace tiller::mission {

bool inside(const FenceShape& s, double north, double east);
// The index of the first shape the point breaks (-1: allowed).
int fence_breach(const std::vector<FenceShape>& fence, double north, double east);
// "inclusion polygon 0" and the like, for messages.
std::string describe_shape(const std::vector<FenceShape>& fence, int k);

// Refuses (config::Error "FILE: item I (command C): ...") a mission whose items cannot be flown:
// a point outside the fence ("... outside the fence (inclusion polygon 0)"), a jump to no item
// or a jump loop that passes no point, a fence shape with fewer than 3 vertices or no radius.
void check_items(const Mission& m, const std::string& file);

}  // namespace tiller::mission
