// Mission files: a path to follow, in local NED metres, from YAML or CSV (config/missions/).
//
// YAML (keys other than `waypoints` optional):
//   name: default
//   description: one line
//   is_translation: false        # hold the final heading while moving (seed 004)
//   start: {north: 0, east: 0, heading_deg: 0}   # where a simulated run starts the vehicle
//   time_limit_s: 170            # simulated time a test or the benchmark allows
//   station_keep_s: 30           # how long to hold the goal after the path is complete
//   depth: 0                     # m below the surface, an ROV's (a boat ignores it)
//   waypoints:                   # each [north, east] m, or {north, east, heading_deg, depth}
//     - [0, 0]
//     - {north: 20, east: 0, heading_deg: 90, depth: 3}   # depth: m, kept by the points after
//   (or `waypoints_csv: file.csv`, relative to the mission file)
// CSV: a header line `north,east` or `north,east,heading_deg`, then one point per line; an
// empty heading cell means no heading (no depth column: an ROV's CSV mission flies at `depth` 0).
// Errors name the file, the line and what was expected. Missions with items (loiter, return home,
// speed, jump, fence; lat/lon or local metres) come from a QGroundControl .plan
// (mission/plan_file.hpp) or our YAML's `items:` (mission/items_yaml.cpp); both parse into this one
// model; docs/missions.md has every format and item.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <tiller/path_t.hpp>

#include "core/config.hpp"

namespace tiller::mission {

struct MissionPoint {
  double north = 0, east = 0;  // m
  bool has_heading = false;
  double heading = 0;  // rad NED
  // m below the surface (NED down, >= 0): where an ROV flies the point (tiller-rov-control's
  // waypointing); 0 for a boat, which ignores it. has_depth: given in the file (a point without
  // one takes the point before it's, the first the mission's `depth`, default 0).
  double depth = 0;
  bool has_depth = false;
};

// A WGS84 position (degrees; altitude m above the ellipsoid, ignored by a boat).
struct GeoPoint {
  double lat_deg = 0, lon_deg = 0, alt_m = 0;
};

// One mission item, what the vehicle does there (docs/missions.md "Items").
enum class ItemKind {
  kWaypoint,    // go to the point (and on)
  kLoiter,      // go to the point, station-keep there loiter_s, then go on (< 0: for ever)
  kReturnHome,  // a path to home (or the nearest rally point), then Mission::return_end
  kStop,        // go to the point (none: where the vehicle is), stop: drop the path and disarm
  kJump,        // go on at item jump_to, `repeat` times (-1: for ever), then past this item
  kSpeed,       // the along-path speed from here on, m/s (<= 0: the follower's max_speed)
};
struct Item {
  ItemKind kind = ItemKind::kWaypoint;
  int index = 0;    // the item's index in its file (0-based, a survey's items share its own)
  int command = 0;  // MAVLink MAV_CMD (.plan), 0 for our YAML
  bool has_point = false;
  MissionPoint point;           // local NED m (from geo by localise())
  std::optional<GeoPoint> geo;  // the point as given in lat/lon
  double loiter_s = -1;         // kLoiter
  double speed = 0;             // kSpeed
  int jump_to = 0;              // kJump: index into Mission::items
  int repeat = 0;               // kJump
};
// A geofence shape: a polygon (>= 3 vertices) or a circle, in local NED m after localise().
struct FenceShape {
  bool inclusion = true;  // true: the vehicle must stay inside; false: must stay out
  bool circle = false;
  std::vector<MissionPoint> polygon;
  std::vector<GeoPoint> geo_polygon;  // as given in lat/lon (empty: given in metres)
  MissionPoint centre;
  std::optional<GeoPoint> geo_centre;
  double radius_m = 0;
};
enum class FenceAction { kHold, kReturn, kNeutral };  // at run time, on leaving the fence
enum class ReturnEnd { kHold, kStop };                // after a return home

struct Mission {
  std::string name;
  std::string description;
  bool is_translation = false;
  std::optional<MissionPoint> start;  // has_heading = whether a start heading was given
  bool start_is_home = false;         // start not given: home (moves with a new datum)
  double time_limit_s = 600;
  double station_keep_s = 0;
  std::vector<MissionPoint> waypoints;  // with items: every item's point, in item order

  // Items (empty: a plain path, `waypoints`, as before). Home is the plan's home position (the
  // return point; the local frame's datum unless another is given), local m in home_point.
  std::vector<Item> items;
  std::optional<GeoPoint> home;
  MissionPoint home_point;
  std::vector<FenceShape> fence;
  FenceAction fence_action = FenceAction::kHold;
  ReturnEnd return_end = ReturnEnd::kHold;
  std::vector<MissionPoint> rally;  // local m
  std::vector<GeoPoint> rally_geo;  // as given
  std::optional<GeoPoint> datum;    // the datum localise() used (empty: all in metres)
  bool geodetic() const;            // anything given in lat/lon
};

// Loads a .yaml/.yml, .csv or QGroundControl .plan mission file; throws config::Error naming the
// file and line (or item). A mission in lat/lon is localised about `datum` when given, else
// about its home; without either it is refused. Items are then checked (check_items).
Mission load_mission_file(const std::string& path, const std::optional<GeoPoint>& datum = {});
Mission load_mission(const config::Value& root, const std::string& base_dir);
// A mission with items: localised (about `datum`, else its home), waypoints from the items, its
// start at home when it names none, then check_items (mission/fence.hpp). Plain paths unchanged.
void finish_items(Mission& m, const std::string& file, const std::optional<GeoPoint>& datum);
// A finished mission in lat/lon converted again, about another datum (the vehicle's TILLER_DATUM):
// every point, the waypoints and a start at home move; checked again. Metres-only: unchanged.
void relocalise(Mission& m, const GeoPoint& datum, const std::string& file);
std::vector<MissionPoint> load_csv_points(const std::string& path);

// The path message for a mission (path_id identifies it: a new id restarts the follower).
path_t to_path(const Mission& m, std::int64_t path_id, std::int64_t utime);
// The points as the path's waypoints (n_waypoints too, position[2] the depth), reusing its storage.
void set_waypoints(path_t& p, const std::vector<MissionPoint>& points);

}  // namespace tiller::mission
