#include "mission/plan_file.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/config.hpp"

namespace tiller::mission {

namespace {

using nlohmann::json;

struct Ctx {
  std::string file;
  Mission& m;
  std::map<long, int> jump_ids;  // doJumpId -> index into m.items of the item at or after it
  std::vector<std::pair<std::size_t, long>> jumps;  // (item, target doJumpId) to resolve
  // mission.vehicleType 12 (MAV_TYPE_SUBMARINE): an item's altitude is minus its depth (ArduSub's
  // and QGroundControl's convention for a submarine); a boat's altitude is ignored.
  bool submarine = false;
};

[[noreturn]] void fail(const std::string& where, const std::string& why) {
  throw config::Error(where + ": " + why);
}

double num(const json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

GeoPoint lat_lon(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() < 2 || !j[0].is_number() || !j[1].is_number())
    fail(where, "expected [latitude, longitude] in degrees");
  GeoPoint g{j[0].get<double>(), j[1].get<double>(), j.size() > 2 ? num(j[2]) : 0.0};
  if (!std::isfinite(g.alt_m)) g.alt_m = 0;
  if (!(std::fabs(g.lat_deg) <= 90) || !(std::fabs(g.lon_deg) <= 180))
    fail(where, "expected a latitude in [-90, 90] and a longitude in [-180, 180] degrees");
  return g;
}

void simple_item(Ctx& c, const json& j, const std::string& where, int index) {
  if (!j.is_object() || !j.contains("command") || !j["command"].is_number_integer())
    fail(where, "expected a SimpleItem with a command number");
  const int cmd = j["command"].get<int>();
  const std::string at = where + " (command " + std::to_string(cmd) + ")";
  const json& pj = j.value("params", json::array());
  if (!pj.is_array() || pj.size() != 7) fail(at, "expected params: 7 numbers (or null)");
  double p[7];
  for (int k = 0; k < 7; ++k) p[k] = num(pj[k]);
  const int frame = j.value("frame", -1);
  const long jump_id = j.value("doJumpId", -1L);
  if (jump_id >= 0) c.jump_ids.emplace(jump_id, static_cast<int>(c.m.items.size()));
  Item it;
  it.index = index;
  it.command = cmd;
  const auto position = [&](bool optional) {
    if (frame == 10 || frame == 11)
      fail(at, "frame " + std::to_string(frame) +
                   " (terrain altitude) is an altitude a boat cannot fly: plan in a global frame "
                   "(0, 3, 5 or 6)");
    if (frame != 0 && frame != 3 && frame != 5 && frame != 6)
      fail(at, "frame " + std::to_string(frame) +
                   ": expected a global frame (0, 3, 5 or 6; the altitude is ignored)");
    if (optional && (!std::isfinite(p[4]) || !std::isfinite(p[5]) || (p[4] == 0 && p[5] == 0)))
      return;
    if (!(std::fabs(p[4]) <= 90) || !(std::fabs(p[5]) <= 180))
      fail(at, "expected params[4], params[5] a latitude and longitude in degrees");
    it.has_point = true;
    it.geo = GeoPoint{p[4], p[5], std::isfinite(p[6]) ? p[6] : 0.0};
    if (c.submarine) {
      if (!(it.geo->alt_m <= 0 && it.geo->alt_m >= -11000))
        fail(at,
             "a submarine's altitude (params[6]) is minus its depth: expected a number in "
             "[-11000, 0] m");
      it.point.depth = -it.geo->alt_m;
      it.point.has_depth = true;
    }
  };
  switch (cmd) {
    case 16:  // NAV_WAYPOINT
      position(false);
      if (std::isfinite(p[0]) && p[0] > 0) {
        it.kind = ItemKind::kLoiter;
        it.loiter_s = p[0];
      }
      break;
    case 17:  // NAV_LOITER_UNLIM
      position(false);
      it.kind = ItemKind::kLoiter;
      it.loiter_s = -1;
      break;
    case 19:  // NAV_LOITER_TIME
      position(false);
      if (!(p[0] >= 0 && p[0] <= 1e6)) fail(at, "expected params[0] a loiter time in [0, 1e6] s");
      it.kind = ItemKind::kLoiter;
      it.loiter_s = p[0];
      break;
    case 20:  // NAV_RETURN_TO_LAUNCH
      it.kind = ItemKind::kReturnHome;
      break;
    case 21:  // NAV_LAND: a boat stops
      position(true);
      it.kind = ItemKind::kStop;
      break;
    case 177:  // DO_JUMP
      if (!(p[0] >= 0) || p[0] != std::floor(p[0]) || !(p[1] >= -1) || p[1] != std::floor(p[1]))
        fail(at, "expected params[0] the doJumpId to jump to, params[1] a repeat count >= -1");
      it.kind = ItemKind::kJump;
      it.repeat = static_cast<int>(p[1]);
      c.jumps.emplace_back(c.m.items.size(), static_cast<long>(p[0]));
      break;
    case 178:                  // DO_CHANGE_SPEED
      if (p[1] == -1) return;  // no change
      if (!(p[1] == -2 || (p[1] > 0 && p[1] <= 20)))
        fail(at, "expected params[1] a speed in (0, 20] m/s, -1 (no change) or -2 (default)");
      it.kind = ItemKind::kSpeed;
      it.speed = p[1] == -2 ? 0 : p[1];
      break;
    case 206:  // DO_SET_CAM_TRIGG_DIST: no camera on our vehicles
      return;
    case 22:
      fail(at, "take-off (NAV_TAKEOFF) is not something a boat can do: remove the item");
    case 181:
    case 182:
    case 183:
    case 184:
      fail(at, "servo and relay commands: the vehicle has no servo or relay outputs");
    default:
      fail(at, "unknown or unsupported command (docs/missions.md lists the supported ones)");
  }
  c.m.items.push_back(it);
}

void complex_item(Ctx& c, const json& j, const std::string& where, int index) {
  const std::string type = j.value("complexItemType", "");
  if (type != "survey" && type != "CorridorScan")
    fail(where, "complex item '" + type + "': expected survey or CorridorScan");
  const json* items = nullptr;
  if (j.contains("TransectStyleComplexItem") && j["TransectStyleComplexItem"].is_object() &&
      j["TransectStyleComplexItem"].contains("Items"))
    items = &j["TransectStyleComplexItem"]["Items"];
  if (items == nullptr || !items->is_array() || items->empty())
    fail(where + " (" + type + ")",
         "expected TransectStyleComplexItem.Items, the generated items (save the plan from "
         "QGroundControl after the survey is drawn)");
  for (std::size_t k = 0; k < items->size(); ++k)
    simple_item(c, (*items)[k], where + " (" + type + ") item " + std::to_string(k), index);
}

}  // namespace

Mission parse_plan(const std::string& text, const std::string& file) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw config::Error(file + ": not JSON (" + std::string(e.what()) + ")");
  }
  if (!root.is_object() || root.value("fileType", "") != "Plan")
    fail(file, "expected a QGroundControl plan (fileType \"Plan\")");
  if (root.value("version", 0) != 1) fail(file, "version: expected 1 (the .plan format)");
  Mission m;
  m.name =
      file.substr(file.find_last_of('/') == std::string::npos ? 0 : file.find_last_of('/') + 1);
  m.description = "QGroundControl plan";
  m.time_limit_s = 3600;
  Ctx c{file, m, {}, {}};
  const json& mis = root.value("mission", json::object());
  if (!mis.is_object() || !mis.contains("items") || !mis["items"].is_array())
    fail(file, "mission.items: expected a list of items");
  c.submarine = mis.value("vehicleType", 0) == 12;
  if (mis.contains("plannedHomePosition"))
    m.home = lat_lon(mis["plannedHomePosition"], file + ": mission.plannedHomePosition");
  const json& items = mis["items"];
  for (std::size_t k = 0; k < items.size(); ++k) {
    const std::string where = file + ": item " + std::to_string(k);
    const std::string type = items[k].is_object() ? items[k].value("type", "") : "";
    if (type == "SimpleItem")
      simple_item(c, items[k], where, static_cast<int>(k));
    else if (type == "ComplexItem")
      complex_item(c, items[k], where, static_cast<int>(k));
    else
      fail(where, "expected type SimpleItem or ComplexItem, got '" + type + "'");
  }
  for (const auto& [item, target] : c.jumps) {
    const auto t = c.jump_ids.find(target);
    if (t == c.jump_ids.end() || t->second >= static_cast<int>(m.items.size()))
      fail(file + ": item " + std::to_string(m.items[item].index) + " (command 177)",
           "jump to doJumpId " + std::to_string(target) + ": no such item");
    m.items[item].jump_to = t->second;
  }
  if (m.items.empty()) fail(file, "mission.items: expected at least one item");
  const json& fence = root.value("geoFence", json::object());
  for (const auto& p : fence.value("polygons", json::array())) {
    FenceShape s;
    s.inclusion = p.value("inclusion", true);
    const std::string where = file + ": geoFence.polygons[" + std::to_string(m.fence.size()) + "]";
    for (const auto& v : p.value("polygon", json::array()))
      s.geo_polygon.push_back(lat_lon(v, where));
    if (s.geo_polygon.size() < 3) fail(where, "expected a polygon of >= 3 [lat, lon] vertices");
    m.fence.push_back(s);
  }
  for (const auto& p : fence.value("circles", json::array())) {
    FenceShape s;
    s.circle = true;
    s.inclusion = p.value("inclusion", true);
    const std::string where = file + ": geoFence.circles[" + std::to_string(m.fence.size()) + "]";
    const json& cj = p.value("circle", json::object());
    s.geo_centre = lat_lon(cj.value("center", json()), where + ".circle.center");
    s.radius_m = num(cj.value("radius", json()));
    if (!(s.radius_m > 0)) fail(where, "circle.radius: expected a radius > 0 m");
    m.fence.push_back(s);
  }
  const json& rally = root.value("rallyPoints", json::object());
  for (const auto& p : rally.value("points", json::array()))
    m.rally_geo.push_back(lat_lon(p, file + ": rallyPoints.points"));
  return m;
}

Mission load_plan_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw config::Error(path + ": cannot open the plan file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_plan(ss.str(), path);
}

}  // namespace tiller::mission
