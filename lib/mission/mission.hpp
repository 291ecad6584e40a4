// Mission files: a path to follow, in local NED metres, from YAML or CSV (config/missions/).
//
// YAML (keys other than `waypoints` optional):
//   name: default
//   description: one line
//   is_translation: false        # hold the final heading while moving (seed 004)
//   start: {north: 0, east: 0, heading_deg: 0}   # where a simulated run starts the vehicle
//   time_limit_s: 170            # simulated time a test or the benchmark allows
//   station_keep_s: 30           # how long to hold the goal after the path is complete
//   waypoints:                   # each [north, east] m, or {north, east, heading_deg}
//     - [0, 0]
//     - {north: 20, east: 0, heading_deg: 90}
//   (or `waypoints_csv: file.csv`, relative to the mission file)
// CSV: a header line `north,east` or `north,east,heading_deg`, then one point per line; an
// empty heading cell means no heading. Errors name the file, the line and what was expected.
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
};

struct Mission {
  std::string name;
  std::string description;
  bool is_translation = false;
  std::optional<MissionPoint> start;  // has_heading = whether a start heading was given
  double time_limit_s = 600;
  double station_keep_s = 0;
  std::vector<MissionPoint> waypoints;
};

// Loads a .yaml/.yml or .csv mission file; throws config::Error naming the file and line.
Mission load_mission_file(const std::string& path);
Mission load_mission(const config::Value& root, const std::string& base_dir);
std::vector<MissionPoint> load_csv_points(const std::string& path);

// The path message for a mission (path_id identifies it: a new id restarts the follower).
path_t to_path(const Mission& m, std::int64_t path_id, std::int64_t utime);

}  // namespace tiller::mission
