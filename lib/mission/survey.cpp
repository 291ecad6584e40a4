#include "mission/survey.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "core/angles.hpp"
#include "core/config.hpp"
#include "mission/fence.hpp"
#include "mission/geo.hpp"

namespace tiller::mission {

namespace {
struct XY {
  double x, y;  // x along the lanes, y across
};
}  // namespace

Survey plan_survey(const std::vector<MissionPoint>& poly, const SurveyParams& p) {
  if (poly.size() < 3) throw std::runtime_error("survey: expected a polygon of >= 3 vertices");
  if (!(p.spacing_m > 0)) throw std::runtime_error("survey: expected a spacing > 0 m");
  const double a = deg_to_rad(p.angle_deg);
  const double c = std::cos(a), s = std::sin(a);  // lane direction (north c, east s)
  std::vector<XY> q;
  for (const auto& v : poly) q.push_back({v.north * c + v.east * s, -v.north * s + v.east * c});
  const auto back = [&](double x, double y) {
    MissionPoint m;
    m.north = x * c - y * s;
    m.east = x * s + y * c;
    return m;
  };
  double ymin = 1e18, ymax = -1e18;
  for (const auto& v : q) ymin = std::min(ymin, v.y), ymax = std::max(ymax, v.y);
  // Lines across, each with its clipped lanes (crossing pairs, in x order).
  std::vector<std::vector<std::pair<double, double>>> lines;
  std::vector<double> ys;
  for (double y = ymin + p.spacing_m / 2; y < ymax; y += p.spacing_m) {
    std::vector<double> xs;
    for (std::size_t i = 0, j = q.size() - 1; i < q.size(); j = i++)
      if ((q[i].y > y) != (q[j].y > y))
        xs.push_back(q[i].x + (y - q[i].y) * (q[j].x - q[i].x) / (q[j].y - q[i].y));
    std::sort(xs.begin(), xs.end());
    std::vector<std::pair<double, double>> segs;
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2)
      if (xs[k + 1] - xs[k] > 1e-6) segs.emplace_back(xs[k], xs[k + 1]);
    lines.push_back(segs);
    ys.push_back(y);
  }
  std::size_t columns = 0;
  for (const auto& l : lines) columns = std::max(columns, l.size());
  if (columns == 0) throw std::runtime_error("survey: no lane fits in the polygon");
  const int skip = p.turn_radius_m > 0
                       ? std::max(1, static_cast<int>(std::ceil(2 * p.turn_radius_m / p.spacing_m)))
                       : 1;
  Survey out;
  bool forward = true;
  const double r = p.turn_radius_m;
  for (std::size_t col = 0; col < columns; ++col) {
    for (int start = 0; start < skip; ++start) {
      for (std::size_t li = start; li < lines.size(); li += skip) {
        if (col >= lines[li].size()) continue;
        const auto [x0, x1] = lines[li][col];
        const double from = forward ? x0 : x1, to = forward ? x1 : x0, dir = forward ? 1 : -1;
        const double y = ys[li];
        out.lanes.push_back({back(from, y), back(to, y)});
        if (r > 0) out.points.push_back(back(from - dir * r, y));
        out.points.push_back(back(from, y));
        out.points.push_back(back(to, y));
        if (r > 0) out.points.push_back(back(to + dir * r, y));
        forward = !forward;
      }
    }
  }
  // Coverage on a 0.25 m grid over the polygon's bounding box.
  FenceShape shape;
  shape.polygon = poly;
  double nmin = 1e18, nmax = -1e18, emin = 1e18, emax = -1e18;
  for (const auto& v : poly) {
    nmin = std::min(nmin, v.north), nmax = std::max(nmax, v.north);
    emin = std::min(emin, v.east), emax = std::max(emax, v.east);
  }
  constexpr double kCell = 0.25;
  long inside_cells = 0, covered = 0;
  for (double n = nmin + kCell / 2; n < nmax; n += kCell) {
    for (double e = emin + kCell / 2; e < emax; e += kCell) {
      if (!inside(shape, n, e)) continue;
      ++inside_cells;
      for (const auto& l : out.lanes) {
        const double dn = l.b.north - l.a.north, de = l.b.east - l.a.east;
        const double len2 = dn * dn + de * de;
        const double t = std::clamp(((n - l.a.north) * dn + (e - l.a.east) * de) / len2, 0.0, 1.0);
        if (std::hypot(n - l.a.north - t * dn, e - l.a.east - t * de) <= p.spacing_m / 2 + 1e-9) {
          ++covered;
          break;
        }
      }
    }
  }
  out.polygon_area_m2 = inside_cells * kCell * kCell;
  out.coverage = inside_cells > 0 ? static_cast<double>(covered) / inside_cells : 0.0;
  return out;
}

std::vector<GeoPoint> load_geojson_polygon(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw config::Error(path + ": cannot open the GeoJSON file");
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ss.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw config::Error(path + ": not JSON (" + std::string(e.what()) + ")");
  }
  if (j.value("type", "") == "FeatureCollection" && j.contains("features") &&
      !j["features"].empty())
    j = j["features"][0];
  if (j.value("type", "") == "Feature") j = j.value("geometry", nlohmann::json::object());
  if (j.value("type", "") != "Polygon" || !j.contains("coordinates") ||
      !j["coordinates"].is_array() || j["coordinates"].empty())
    throw config::Error(path +
                        ": expected a GeoJSON Polygon (RFC 7946: coordinates [[[lon, lat], ...]])");
  std::vector<GeoPoint> out;
  for (const auto& v : j["coordinates"][0]) {
    if (!v.is_array() || v.size() < 2 || !v[0].is_number() || !v[1].is_number())
      throw config::Error(path + ": expected [longitude, latitude] pairs");
    out.push_back({v[1].get<double>(), v[0].get<double>(), 0});
  }
  if (out.size() > 1 && out.front().lat_deg == out.back().lat_deg &&
      out.front().lon_deg == out.back().lon_deg)
    out.pop_back();  // GeoJSON closes its rings
  if (out.size() < 3) throw config::Error(path + ": expected a polygon of >= 3 vertices");
  return out;
}

std::string survey_plan_json(const Survey& s, const GeoPoint& home) {
  using nlohmann::json;
  const LocalFrame f(home);
  json items = json::array();
  int id = 1;
  for (const auto& p : s.points) {
    const GeoPoint g = f.to_geo(p.north, p.east);
    items.push_back({{"AMSLAltAboveTerrain", nullptr},
                     {"Altitude", 0},
                     {"AltitudeMode", 1},
                     {"autoContinue", true},
                     {"command", 16},
                     {"doJumpId", id++},
                     {"frame", 3},
                     {"params", {0, 0, 0, nullptr, g.lat_deg, g.lon_deg, 0}},
                     {"type", "SimpleItem"}});
  }
  items.push_back({{"autoContinue", true},
                   {"command", 20},
                   {"doJumpId", id},
                   {"frame", 2},
                   {"params", {0, 0, 0, 0, 0, 0, 0}},
                   {"type", "SimpleItem"}});
  json plan = {
      {"fileType", "Plan"},
      {"geoFence", {{"circles", json::array()}, {"polygons", json::array()}, {"version", 2}}},
      {"groundStation", "tiller-mission survey"},
      {"mission",
       {{"cruiseSpeed", 1.5},
        {"firmwareType", 3},
        {"globalPlanAltitudeMode", 1},
        {"hoverSpeed", 1},
        {"items", items},
        {"plannedHomePosition", {home.lat_deg, home.lon_deg, home.alt_m}},
        {"vehicleType", 11},
        {"version", 2}}},
      {"rallyPoints", {{"points", json::array()}, {"version", 2}}},
      {"version", 1}};
  std::ostringstream os;
  os << plan.dump(4) << "\n";
  return os.str();
}

}  // namespace tiller::mission
