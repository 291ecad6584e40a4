// Our YAML's items (docs/missions.md "Our YAML"): `items:` instead of `waypoints:`, each
//   {do: waypoint, lat: 63.44, lon: 10.4}         (or north: / east: m, or [north, east])
//   {do: loiter, lat, lon, time_s: 30}            (no time_s: for ever)
//   {do: speed, speed: 1.0}                       (m/s from here on; 0: the follower's max)
//   {do: jump, to: 1, repeat: 2}                  (to: an item index, 0-based; repeat -1: ever)
//   {do: return_home}   {do: stop}   {do: stop, lat, lon}
// and `home: {lat, lon, alt}`, `fence: {action: hold|return|neutral, inclusion: [...],
// exclusion: [...]}` (each a list of points, or {circle: POINT, radius_m: R}), `rally: [POINT...]`,
// `return_end: hold|stop`.
#include "mission/items_yaml.hpp"

namespace tiller::mission {

namespace {

// A point: {lat, lon[, alt]} (geodetic) or {north, east} / [north, east] (m).
void load_place(const config::Value& v, MissionPoint& p, std::optional<GeoPoint>& geo) {
  if (v.is_map() && v.has("lat")) {
    GeoPoint g;
    g.lat_deg = v.number("lat", {-90, 90});
    g.lon_deg = v.number("lon", {-180, 180});
    g.alt_m = v.number_or("alt", 0, {-1e4, 1e5});
    geo = g;
    return;
  }
  if (v.is_sequence()) {
    const auto xy = v.as_numbers(2, {-1e6, 1e6});
    p.north = xy[0];
    p.east = xy[1];
    return;
  }
  if (!v.is_map()) v.fail("{lat, lon}, {north, east} or [north, east]");
  p.north = v.number("north", {-1e6, 1e6});
  p.east = v.number("east", {-1e6, 1e6});
}

bool has_place(const config::Value& v) {
  return v.has("lat") || v.has("north");
}

std::vector<FenceShape> load_shapes(const config::Value& list, bool inclusion) {
  std::vector<FenceShape> out;
  if (!list.is_sequence()) list.fail("a list of polygons (lists of points) or circles");
  for (const auto& sv : list.items()) {
    FenceShape s;
    s.inclusion = inclusion;
    if (sv.is_map()) {
      s.circle = true;
      MissionPoint c;
      load_place(sv.at("circle"), c, s.geo_centre);
      s.centre = c;
      s.radius_m = sv.number("radius_m", {1e-3, 1e6});
    } else {
      if (!sv.is_sequence() || sv.size() < 3) sv.fail("a polygon of >= 3 points");
      bool geo_any = false;
      for (const auto& pv : sv.items()) {
        MissionPoint p;
        std::optional<GeoPoint> g;
        load_place(pv, p, g);
        if (g) s.geo_polygon.push_back(*g);
        geo_any |= g.has_value();
        s.polygon.push_back(p);
      }
      if (geo_any && s.geo_polygon.size() != s.polygon.size())
        sv.fail("every vertex in lat/lon or every vertex in metres");
      if (geo_any) s.polygon.clear();
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace

void load_items(const config::Value& root, Mission& m) {
  if (auto h = root.find("home")) {
    MissionPoint unused;
    std::optional<GeoPoint> g;
    load_place(*h, unused, g);
    if (!g) h->fail("{lat, lon, alt} (home is a geodetic position)");
    m.home = g;
  }
  const auto items = root.at("items");
  if (!items.is_sequence() || items.size() == 0) items.fail("a non-empty list of items");
  int k = 0;
  for (const auto& v : items.items()) {
    Item it;
    it.index = k++;
    if (v.is_sequence()) {  // [north, east]: a waypoint
      load_place(v, it.point, it.geo);
      it.has_point = true;
      m.items.push_back(it);
      continue;
    }
    if (!v.is_map()) v.fail("an item: {do: waypoint|loiter|speed|jump|return_home|stop, ...}");
    const std::string what =
        v.choice("do", {"waypoint", "loiter", "speed", "jump", "return_home", "stop"});
    if (what == "waypoint" || what == "loiter" || (what == "stop" && has_place(v))) {
      load_place(v, it.point, it.geo);
      it.has_point = true;
    }
    if (what == "loiter") {
      it.kind = ItemKind::kLoiter;
      it.loiter_s = v.number_or("time_s", -1, {0, 1e6});
    } else if (what == "speed") {
      it.kind = ItemKind::kSpeed;
      it.speed = v.number("speed", {0, 20});
    } else if (what == "jump") {
      it.kind = ItemKind::kJump;
      it.jump_to = static_cast<int>(v.integer("to", 0, 100000));
      it.repeat = static_cast<int>(v.integer("repeat", -1, 100000));
    } else if (what == "return_home") {
      it.kind = ItemKind::kReturnHome;
    } else if (what == "stop") {
      it.kind = ItemKind::kStop;
    }
    v.check_all_used();
    m.items.push_back(it);
  }
  if (auto f = root.find("fence")) {
    const std::string a = f->choice_or("action", "hold", {"hold", "return", "neutral"});
    m.fence_action = a == "hold"     ? FenceAction::kHold
                     : a == "return" ? FenceAction::kReturn
                                     : FenceAction::kNeutral;
    for (const char* kind : {"inclusion", "exclusion"})
      if (auto l = f->find(kind))
        for (auto& s : load_shapes(*l, kind[0] == 'i')) m.fence.push_back(s);
  }
  if (auto r = root.find("rally")) {
    if (!r->is_sequence()) r->fail("a list of points");
    for (const auto& pv : r->items()) {
      MissionPoint p;
      std::optional<GeoPoint> g;
      load_place(pv, p, g);
      if (g)
        m.rally_geo.push_back(*g);
      else
        m.rally.push_back(p);
    }
    if (!m.rally_geo.empty() && !m.rally.empty()) r->fail("every point in lat/lon or in metres");
  }
  m.return_end = root.choice_or("return_end", "hold", {"hold", "stop"}) == "hold"
                     ? ReturnEnd::kHold
                     : ReturnEnd::kStop;
}

}  // namespace tiller::mission
