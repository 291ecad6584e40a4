// tiller-nav: the estimator. GNSS, IMU, heading and depth in -> TILLER_ODOMETRY with covariance
// and validity bits. See lib/nav/nav_node.hpp and docs/navigation.md. The datum of local NED is
// the config's, or --datum LAT,LON[,ALT] (a launch file's), or --datum-mission FILE (that
// mission's home, so the estimator and tiller-mission localise about the same point).
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "mission/mission.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

namespace {

// "LAT,LON[,ALT]" in WGS84 degrees and metres above the ellipsoid; throws naming --datum.
std::vector<double> parse_datum(const std::string& text) {
  std::vector<double> v;
  bool ok = true;
  for (const std::string& item : tiller::app::split_list(text)) {
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(item.c_str(), &end);
    ok = ok && end == item.c_str() + item.size() && errno == 0 && std::isfinite(x);
    v.push_back(x);
  }
  if (!ok || v.size() < 2 || v.size() > 3 || std::fabs(v[0]) > 90 || std::fabs(v[1]) > 180)
    throw std::runtime_error(
        "--datum: expected LAT,LON[,ALT] in degrees (latitude -90..90, "
        "longitude -180..180) and metres, got '" +
        text + "'");
  if (v.size() == 2) v.push_back(0.0);
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-nav",
      "Estimates the vehicle's state -> TILLER_ODOMETRY",
      "config/nav/usv.yaml",
      {{"datum", "LAT,LON[,ALT]", "the datum of local NED (instead of the config's)", ""},
       {"datum-mission", "FILE", "the datum is this mission's home (.yaml or .plan)", ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    nav::NavParams p = nav::load_nav_file(args.config);
    if (!args.get("datum").empty() && !args.get("datum-mission").empty())
      throw std::runtime_error("--datum and --datum-mission: give one");
    if (!args.get("datum").empty()) {
      const std::vector<double> d = parse_datum(args.get("datum"));
      p.fixed_datum = true;
      p.datum_latitude_deg = d[0];
      p.datum_longitude_deg = d[1];
      p.datum_altitude_m = d[2];
    } else if (!args.get("datum-mission").empty()) {
      const std::string file = app::resolve_path(args.get("datum-mission"));
      const mission::Mission m = mission::load_mission_file(file);
      if (!m.home)
        throw std::runtime_error("--datum-mission " + file +
                                 ": the mission has no home position (home: {lat, lon} in our "
                                 "YAML, plannedHomePosition in a .plan)");
      p.fixed_datum = true;
      p.datum_latitude_deg = m.home->lat_deg;
      p.datum_longitude_deg = m.home->lon_deg;
      p.datum_altitude_m = m.home->alt_m;
    }
    if (p.fixed_datum)
      std::fprintf(stderr, "tiller-nav: datum %.7f, %.7f, %.2f m\n", p.datum_latitude_deg,
                   p.datum_longitude_deg, p.datum_altitude_m);
    nav::NavNode node(p);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
