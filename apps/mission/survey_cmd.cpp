// tiller-mission survey POLYGON.geojson [--spacing M] [--angle DEG] [--vehicle FILE]
//   [--turn-radius-m R] [--home LAT,LON] [--out FILE.plan]: a lawnmower over the GeoJSON polygon
// (mission/survey.hpp), written as a QGroundControl plan, its coverage printed. The turning
// radius: --turn-radius-m, else the vehicle's follower, max_speed / turn_rate from
// config/guidance/<vehicle>.yaml (the follower's own R = U / turn_rate). Home (the datum):
// --home, else the polygon's first vertex. Bad values exit 2 naming the flag.
#include "survey_cmd.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "core/config.hpp"
#include "mission/geo.hpp"
#include "mission/survey.hpp"
#include "runtime/app.hpp"

namespace {

double number(const std::string& flag, const std::string& v, double lo, double hi) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (...) {
    used = 0;
  }
  if (used != v.size() || !(x >= lo && x <= hi))
    throw std::runtime_error("--" + flag + ": expected a number in [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "], got '" + v + "'");
  return x;
}

}  // namespace

int survey_main(int argc, char** argv) {
  using namespace tiller;
  try {
    std::string polygon, out, vehicle = "config/vehicles/otter.yaml", home_text;
    mission::SurveyParams p;
    double radius = -1;
    for (int k = 2; k < argc; ++k) {
      const std::string a = argv[k];
      const auto value = [&]() -> std::string {
        if (k + 1 >= argc) throw std::runtime_error(a + ": expected a value");
        return argv[++k];
      };
      if (a == "--spacing")
        p.spacing_m = number("spacing", value(), 0.1, 1000);
      else if (a == "--angle")
        p.angle_deg = number("angle", value(), -360, 360);
      else if (a == "--turn-radius-m")
        radius = number("turn-radius-m", value(), 0, 1000);
      else if (a == "--vehicle")
        vehicle = value();
      else if (a == "--home")
        home_text = value();
      else if (a == "--out")
        out = value();
      else if (a == "--help" || a == "-h") {
        std::cout << "usage: tiller-mission survey POLYGON.geojson [--spacing M] [--angle DEG] "
                     "[--vehicle FILE] [--turn-radius-m R] [--home LAT,LON] [--out FILE.plan]\n";
        return 0;
      } else if (polygon.empty() && a.rfind("--", 0) != 0)
        polygon = a;
      else
        throw std::runtime_error("unknown argument '" + a + "'");
    }
    if (polygon.empty()) throw std::runtime_error("expected POLYGON.geojson");
    if (radius < 0) {
      const std::string stem = std::filesystem::path(vehicle).stem().string();
      const auto g =
          config::Value::load_file(app::resolve_path("config/guidance/" + stem + ".yaml"));
      const auto f = g.at("follower");
      const double u = f.number("max_speed", {0.01, 10}), w = f.number_or("turn_rate", 0, {0, 10});
      radius = w > 0 ? u / w : 0;
    }
    p.turn_radius_m = radius;
    const auto geo = mission::load_geojson_polygon(polygon);
    mission::GeoPoint home = geo.front();
    if (!home_text.empty()) {
      const auto comma = home_text.find(',');
      if (comma == std::string::npos) throw std::runtime_error("--home: expected LAT,LON");
      home.lat_deg = number("home", home_text.substr(0, comma), -90, 90);
      home.lon_deg = number("home", home_text.substr(comma + 1), -180, 180);
    }
    const mission::LocalFrame frame(home);
    std::vector<mission::MissionPoint> local;
    for (const auto& g : geo) local.push_back(frame.to_local(g));
    const auto s = mission::plan_survey(local, p);
    if (out.empty()) out = std::filesystem::path(polygon).replace_extension(".plan").string();
    std::ofstream(out) << mission::survey_plan_json(s, home);
    std::printf(
        "tiller-mission survey: %zu lanes, spacing %.2f m, angle %.1f deg, turn radius %.2f m; "
        "coverage %.1f %% of %.0f m2; %zu waypoints -> %s\n",
        s.lanes.size(), p.spacing_m, p.angle_deg, p.turn_radius_m, 100 * s.coverage,
        s.polygon_area_m2, s.points.size(), out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "tiller-mission survey: " << e.what() << "\n";
    return 2;
  }
}
