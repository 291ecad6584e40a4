#include "mission/survey.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "core/angles.hpp"
#include "core/config.hpp"
#include "mission/fence.hpp"
#include "mission/geo.hpp"
#include "mission/polygon_path.hpp"

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
  // Cells (a boustrophedon decomposition by lines): a lane continues the cell of the one lane it
  // overlaps on the line before when that lane overlaps only it; any split or merge starts cells.
  struct Row {
    std::size_t line;
    double x0, x1;
  };
  std::vector<std::vector<Row>> cells;
  std::vector<std::vector<int>> cell_of(lines.size());
  const auto overlap = [](std::pair<double, double> u, std::pair<double, double> v) {
    return std::min(u.second, v.second) - std::max(u.first, v.first) > 1e-9;
  };
  for (std::size_t li = 0; li < lines.size(); ++li) {
    for (std::size_t j = 0; j < lines[li].size(); ++j) {
      int cell = -1;
      if (li > 0) {
        int prev = -1, n_prev = 0;
        for (std::size_t k = 0; k < lines[li - 1].size(); ++k)
          if (overlap(lines[li - 1][k], lines[li][j])) prev = static_cast<int>(k), ++n_prev;
        if (n_prev == 1) {
          int n_next = 0;
          for (const auto& seg : lines[li]) n_next += overlap(lines[li - 1][prev], seg);
          if (n_next == 1) cell = cell_of[li - 1][prev];
        }
      }
      if (cell < 0) {
        cell = static_cast<int>(cells.size());
        cells.emplace_back();
      }
      cell_of[li].push_back(cell);
      cells[cell].push_back({li, lines[li][j].first, lines[li][j].second});
    }
  }
  if (cells.empty()) throw std::runtime_error("survey: no lane fits in the polygon");
  const int skip = p.turn_radius_m > 0
                       ? std::max(1, static_cast<int>(std::ceil(2 * p.turn_radius_m / p.spacing_m)))
                       : 1;
  // A cell flown one way: its lanes in order (every skip-th line first), alternate directions.
  const auto fly = [&](std::size_t ci, bool reverse, bool forward) {
    std::vector<Row> rows = cells[ci];
    if (reverse) std::reverse(rows.begin(), rows.end());
    std::vector<Lane> lanes;
    for (int start = 0; start < skip; ++start) {
      for (std::size_t r = start; r < rows.size(); r += skip) {
        const double y = ys[rows[r].line];
        lanes.push_back(forward ? Lane{back(rows[r].x0, y), back(rows[r].x1, y)}
                                : Lane{back(rows[r].x1, y), back(rows[r].x0, y)});
        forward = !forward;
      }
    }
    return lanes;
  };
  // Transits stay inside the polygon; their ends 1 mm into the lanes (off the boundary).
  const PolygonPaths paths(poly, p.spacing_m / 2);
  const auto nudged = [](const MissionPoint& from, const MissionPoint& toward) {
    const double d = std::hypot(toward.north - from.north, toward.east - from.east);
    MissionPoint m = from;
    if (d > 2e-3) {
      m.north += 1e-3 * (toward.north - from.north) / d;
      m.east += 1e-3 * (toward.east - from.east) / d;
    }
    return m;
  };
  const auto transit = [&](const Lane& prev, const Lane& next, double* len) {
    return paths.via(nudged(prev.b, prev.a), nudged(next.a, next.b), len);
  };
  // The cells' order: from each starting cell and way (up to kMaxStarts cells), the nearest
  // (by transit length) unflown cell next; the order with the least transit wins.
  constexpr std::size_t kMaxStarts = 12;
  std::vector<Lane> best;
  double best_len = std::numeric_limits<double>::infinity();
  const std::size_t starts = cells.size() <= kMaxStarts ? cells.size() : 1;
  for (std::size_t s0 = 0; s0 < starts; ++s0) {
    for (int way0 = 0; way0 < 4; ++way0) {
      std::vector<Lane> order = fly(s0, way0 & 1, way0 & 2);
      std::vector<bool> flown(cells.size(), false);
      flown[s0] = true;
      double total = 0;
      for (std::size_t n = 1; n < cells.size(); ++n) {
        double nearest = std::numeric_limits<double>::infinity();
        std::vector<Lane> pick;
        std::size_t pick_cell = 0;
        for (std::size_t ci = 0; ci < cells.size(); ++ci) {
          if (flown[ci]) continue;
          for (int way = 0; way < 4; ++way) {
            auto lanes = fly(ci, way & 1, way & 2);
            double len = 0;
            transit(order.back(), lanes.front(), &len);
            if (len < nearest) nearest = len, pick = std::move(lanes), pick_cell = ci;
          }
        }
        if (pick.empty()) break;  // unreachable inside the polygon: cannot happen for one ring
        flown[pick_cell] = true;
        total += nearest;
        order.insert(order.end(), pick.begin(), pick.end());
      }
      if (total < best_len) best_len = total, best = std::move(order);
    }
  }
  Survey out;
  out.cells = static_cast<int>(cells.size());
  out.lanes = best;
  const double r = p.turn_radius_m;
  for (std::size_t k = 0; k < out.lanes.size(); ++k) {
    const Lane& l = out.lanes[k];
    if (k > 0) {
      const auto v = transit(out.lanes[k - 1], l, nullptr);
      out.points.insert(out.points.end(), v.begin(), v.end());
      out.transit_corners += static_cast<int>(v.size());
    }
    const double len = std::hypot(l.b.north - l.a.north, l.b.east - l.a.east);
    const double un = len > 0 ? (l.b.north - l.a.north) / len : 0;
    const double ue = len > 0 ? (l.b.east - l.a.east) / len : 0;
    MissionPoint in = l.a, outp = l.b;
    in.north -= r * un, in.east -= r * ue;
    outp.north += r * un, outp.east += r * ue;
    if (r > 0) out.points.push_back(in);
    out.points.push_back(l.a);
    out.points.push_back(l.b);
    if (r > 0) out.points.push_back(outp);
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
