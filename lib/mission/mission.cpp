#include "mission/mission.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/angles.hpp"
#include "mission/fence.hpp"
#include "mission/geo.hpp"
#include "mission/items_yaml.hpp"
#include "mission/plan_file.hpp"

namespace tiller::mission {

namespace {

MissionPoint load_point(const config::Value& v) {
  MissionPoint p;
  if (v.is_sequence()) {
    const auto xy = v.as_numbers(2, {-1e6, 1e6});
    p.north = xy[0];
    p.east = xy[1];
    return p;
  }
  if (!v.is_map()) v.fail("[north, east] or {north, east, heading_deg, depth}");
  p.north = v.number("north", {-1e6, 1e6});
  p.east = v.number("east", {-1e6, 1e6});
  if (v.has("depth")) {
    p.has_depth = true;
    p.depth = v.number("depth", {0, 11000});
  }
  if (v.has("heading_deg")) {
    p.has_heading = true;
    p.heading = wrap_pi(v.angle_deg("heading_deg", {-360, 360}));
  }
  return p;
}

std::string dir_of(const std::string& path) {
  const auto k = path.find_last_of('/');
  return k == std::string::npos ? std::string(".") : path.substr(0, k);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto a = cell.find_first_not_of(" \t\r");
    const auto b = cell.find_last_not_of(" \t\r");
    out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

}  // namespace

std::vector<MissionPoint> load_csv_points(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw config::Error(path + ": cannot open the mission file");
  std::string line;
  int lineno = 0;
  bool header = false, with_heading = false;
  std::vector<MissionPoint> pts;
  auto fail = [&](const std::string& what) {
    throw config::Error(path + ":" + std::to_string(lineno) + ": expected " + what + ", got '" +
                        line + "'");
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    const auto cells = split_csv(line);
    if (!header) {
      if (cells.size() == 2 && cells[0] == "north" && cells[1] == "east") {
      } else if (cells.size() == 3 && cells[0] == "north" && cells[1] == "east" &&
                 cells[2] == "heading_deg") {
        with_heading = true;
      } else {
        fail("the header 'north,east' or 'north,east,heading_deg'");
      }
      header = true;
      continue;
    }
    if (cells.size() != (with_heading ? 3u : 2u)) fail(with_heading ? "3 columns" : "2 columns");
    MissionPoint p;
    double v[3] = {0, 0, 0};
    for (std::size_t k = 0; k < cells.size(); ++k) {
      if (k == 2 && cells[k].empty()) break;
      std::size_t used = 0;
      try {
        v[k] = std::stod(cells[k], &used);
      } catch (...) {
        used = 0;
      }
      if (used != cells[k].size() || !std::isfinite(v[k]) || std::abs(v[k]) > 1e6) {
        fail("numbers within +-1e6");
      }
      if (k == 2) p.has_heading = true;
    }
    p.north = v[0];
    p.east = v[1];
    p.heading = wrap_pi(deg_to_rad(v[2]));
    pts.push_back(p);
  }
  if (!header) throw config::Error(path + ": empty mission file (expected a header line)");
  if (pts.empty()) throw config::Error(path + ": expected at least one waypoint");
  return pts;
}

Mission load_mission(const config::Value& root, const std::string& base_dir) {
  Mission m;
  m.name = root.string_or("name", "mission");
  m.description = root.string_or("description", "");
  m.is_translation = root.boolean_or("is_translation", false);
  m.time_limit_s = root.number_or("time_limit_s", 600, {1, 1e6});
  m.station_keep_s = root.number_or("station_keep_s", 0, {0, 1e6});
  if (auto s = root.find("start")) m.start = load_point(*s);
  if (int{root.has("waypoints")} + root.has("waypoints_csv") + root.has("items") != 1) {
    root.fail("exactly one of 'waypoints', 'waypoints_csv' or 'items'");
  }
  if (root.has("items")) {
    load_items(root, m);
  } else if (root.has("waypoints")) {
    const auto w = root.at("waypoints");
    if (!w.is_sequence() || w.size() == 0) w.fail("a non-empty list of waypoints");
    for (const auto& item : w.items()) m.waypoints.push_back(load_point(item));
  } else {
    m.waypoints = load_csv_points(base_dir + "/" + root.string("waypoints_csv"));
  }
  // A point without a depth keeps the one before it (the first: the mission's `depth`).
  double depth = root.number_or("depth", 0, {0, 11000});
  for (auto& w : m.waypoints) {
    if (!w.has_depth) w.depth = depth;
    depth = w.depth;
  }
  root.check_all_used();
  return m;
}

namespace {
// After localise(): the waypoints from the items, the start at home unless given, the checks.
void derive(Mission& m, const std::string& file) {
  if (!m.home && m.start && !m.start_is_home) m.home_point = *m.start;
  m.waypoints.clear();
  for (const auto& it : m.items) {
    if (it.has_point) m.waypoints.push_back(it.point);
    // Home is where a return goes without rally points (with them: the nearest, at run time).
    if (it.kind == ItemKind::kReturnHome && m.rally.empty()) m.waypoints.push_back(m.home_point);
  }
  if (!m.start || m.start_is_home) {
    m.start = m.home_point;
    m.start->has_heading = false;
    m.start_is_home = true;
  }
  check_items(m, file);
}
}  // namespace

void finish_items(Mission& m, const std::string& file, const std::optional<GeoPoint>& datum) {
  if (m.items.empty()) return;
  if (m.geodetic()) {
    const auto d = datum ? datum : m.home;
    if (!d)
      throw config::Error(file +
                          ": the mission is in lat/lon: expected a home position (home: {lat, "
                          "lon}, or a .plan's plannedHomePosition) or a datum to place it");
    localise(m, *d);
  }
  derive(m, file);
}

void relocalise(Mission& m, const GeoPoint& datum, const std::string& file) {
  if (m.items.empty() || !m.geodetic()) return;
  localise(m, datum);
  derive(m, file);
}

Mission load_mission_file(const std::string& path, const std::optional<GeoPoint>& datum) {
  const auto ext = path.substr(
      path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  if (ext == ".csv") {
    Mission m;
    m.name = path;
    m.waypoints = load_csv_points(path);
    return m;
  }
  Mission m = ext == ".plan" ? load_plan_file(path)
                             : load_mission(config::Value::load_file(path), dir_of(path));
  finish_items(m, path, datum);
  return m;
}

path_t to_path(const Mission& m, std::int64_t path_id, std::int64_t utime) {
  path_t p{};
  p.utime = utime;
  p.path_id = path_id;
  set_waypoints(p, m.waypoints);
  return p;
}

void set_waypoints(path_t& p, const std::vector<MissionPoint>& points) {
  p.waypoints.clear();
  for (const auto& w : points) {
    waypoint_t x{};
    x.position[0] = w.north;
    x.position[1] = w.east;
    x.position[2] = w.depth;
    x.has_heading = w.has_heading;
    x.heading = w.heading;
    p.waypoints.push_back(x);
  }
  p.n_waypoints = static_cast<std::int32_t>(p.waypoints.size());
}

}  // namespace tiller::mission
