#include "mission/geo.hpp"

namespace tiller::mission {

LocalFrame::LocalFrame(const GeoPoint& d) : lc_(d.lat_deg, d.lon_deg, d.alt_m), alt_(d.alt_m) {}

MissionPoint LocalFrame::to_local(const GeoPoint& p) const {
  double x = 0, y = 0, z = 0;  // east, north, up
  lc_.Forward(p.lat_deg, p.lon_deg, alt_, x, y, z);
  MissionPoint m;
  m.north = y;
  m.east = x;
  return m;
}

GeoPoint LocalFrame::to_geo(double north, double east) const {
  GeoPoint g;
  lc_.Reverse(east, north, 0, g.lat_deg, g.lon_deg, g.alt_m);
  return g;
}

void localise(Mission& m, const GeoPoint& datum) {
  const LocalFrame f(datum);
  m.datum = datum;
  const auto put = [&](MissionPoint& p, const GeoPoint& g) {
    const MissionPoint l = f.to_local(g);
    p.north = l.north;
    p.east = l.east;
  };
  if (m.home) put(m.home_point, *m.home);
  for (auto& it : m.items)
    if (it.geo) put(it.point, *it.geo);
  for (auto& s : m.fence) {
    if (s.geo_centre) put(s.centre, *s.geo_centre);
    if (!s.geo_polygon.empty()) {
      s.polygon.resize(s.geo_polygon.size());
      for (std::size_t k = 0; k < s.geo_polygon.size(); ++k) put(s.polygon[k], s.geo_polygon[k]);
    }
  }
  if (!m.rally_geo.empty()) {
    m.rally.resize(m.rally_geo.size());
    for (std::size_t k = 0; k < m.rally_geo.size(); ++k) put(m.rally[k], m.rally_geo[k]);
  }
}

bool Mission::geodetic() const {
  if (home || !rally_geo.empty()) return true;
  for (const auto& it : items)
    if (it.geo) return true;
  for (const auto& s : fence)
    if (s.geo_centre || !s.geo_polygon.empty()) return true;
  return false;
}

}  // namespace tiller::mission
