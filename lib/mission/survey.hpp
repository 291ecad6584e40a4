// mission::plan_survey: a lawnmower over a polygon (local NED m; concave allowed): lanes along
// `angle_deg` (clockwise from north), `spacing_m` apart, the first and last spacing / 2 inside the
// polygon's extent, each clipped to the polygon (a line crossing a concave polygon gives several
// lanes). Within a cell (below), alternate directions, and when spacing < 2 * turn_radius (a U-turn
// the vehicle cannot make between neighbours) every k-th line first (k = ceil(2 R / spacing)), then
// the ones between, as QGroundControl's "fly alternate transects" does; each lane's ends are
// extended by the turn radius (the turn-around, outside the lane) so the vehicle is on the lane's
// line at its start. Concave polygons: the lines' lanes form cells (a boustrophedon decomposition:
// a split or a merge of lanes from one line to the next starts new cells); each cell is flown
// whole, the cells in the order with the least transit (from each start, the nearest cell next),
// and a transit between lanes that would leave the polygon bends at its vertices, spacing / 2
// inside (mission/polygon_path.hpp). Coverage: the fraction of the polygon's area within spacing /
// 2 of a lane (a 0.25 m grid).
#pragma once

#include <string>
#include <vector>

#include "mission/mission.hpp"

namespace tiller::mission {

struct SurveyParams {
  double spacing_m = 5;
  double angle_deg = 0;
  double turn_radius_m = 0;
};
struct Lane {
  MissionPoint a, b;  // flown from a to b, clipped to the polygon
};
struct Survey {
  std::vector<Lane> lanes;  // in the order flown
  std::vector<MissionPoint>
      points;               // the path: per lane, [transit corners], lead-in, a, b, lead-out
  double coverage = 0;      // 0..1
  int cells = 0;            // the decomposition's cells
  int transit_corners = 0;  // corners added so that transits stay inside the polygon
  double polygon_area_m2 = 0;
};

// Throws std::runtime_error for fewer than 3 vertices, spacing <= 0 or a polygon no lane fits.
Survey plan_survey(const std::vector<MissionPoint>& polygon, const SurveyParams& p);

// A GeoJSON file's first Polygon (a Feature, FeatureCollection or bare geometry; [lon, lat]
// pairs, the outer ring). Throws config::Error naming the file.
std::vector<GeoPoint> load_geojson_polygon(const std::string& path);
// The survey as a QGroundControl plan (waypoints 16 in frame 3, home at `home`), JSON text.
std::string survey_plan_json(const Survey& s, const GeoPoint& home);

}  // namespace tiller::mission
