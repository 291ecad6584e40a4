// QGroundControl .plan files (JSON, fileType "Plan", version 1), as QGroundControl writes them
// (https://docs.qgroundcontrol.com/master/en/qgc-dev-guide/file_formats/plan.html), into the one
// mission model (mission/mission.hpp), in lat/lon: localise() (mission/geo.hpp) gives metres.
//
// mission.items, each "SimpleItem" {command, frame, params[7], doJumpId, autoContinue} or
// "ComplexItem" ("survey", "CorridorScan": their generated TransectStyleComplexItem.Items):
//   16 NAV_WAYPOINT       waypoint (params[0] > 0: a loiter of that many s at it)
//   17 NAV_LOITER_UNLIM   loiter at the point for ever (station keeping; the mission ends there)
//   19 NAV_LOITER_TIME    loiter params[0] s at the point, then go on
//   20 NAV_RETURN_TO_LAUNCH  path home (the nearest rally point if nearer), then hold or stop
//   21 NAV_LAND           boats: go to the point (0, 0 or none: where the vehicle is) and stop
//   177 DO_JUMP           to the item with doJumpId params[0], params[1] times (-1: for ever)
//   178 DO_CHANGE_SPEED   params[1] m/s from here on (-1: no change, -2: back to the default)
//   206 DO_SET_CAM_TRIGG_DIST  (QGroundControl's survey camera trigger) ignored: no camera
// Positions are params[4], params[5] (lat, lon deg) in a global frame (0, 3, 5, 6; a boat's
// altitude is ignored; with mission.vehicleType 12, a submarine, params[6] is minus the depth, as
// ArduSub plans it, and must be <= 0). Refused, the whole plan, with "FILE: item I (command C):
// why": take-off (22) and every other command, a terrain or local frame, a position that is not a
// lat/lon, servo and relay commands (181-184: no outputs on our vehicles).
// mission.plannedHomePosition is home. geoFence.polygons [{inclusion, polygon [[lat, lon]...]}],
// geoFence.circles [{inclusion, circle {center [lat, lon], radius m}}]; rallyPoints.points [[lat,
// lon, alt]].
#pragma once

#include <string>

#include "mission/mission.hpp"

namespace tiller::mission {

// `file` names the source in errors (config::Error).
Mission parse_plan(const std::string& json_text, const std::string& file);
Mission load_plan_file(const std::string& path);

}  // namespace tiller::mission
