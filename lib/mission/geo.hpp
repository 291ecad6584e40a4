// Lat/lon (WGS84) to the local frame and back, with GeographicLib's LocalCartesian (Debian
// libgeographiclib-dev;
// https://geographiclib.sourceforge.io/C++/doc/classGeographicLib_1_1LocalCartesian.html): local
// NED metres about a datum (north, east; down ignored: a boat's altitude is the water's).
// localise() converts every lat/lon a mission holds (items, fence, rally points, home) and
// rewrites Mission::waypoints from the items; the datum is kept in Mission::datum.
#pragma once

#include <GeographicLib/LocalCartesian.hpp>

#include "mission/mission.hpp"

namespace tiller::mission {

class LocalFrame {
 public:
  explicit LocalFrame(const GeoPoint& datum);
  MissionPoint to_local(const GeoPoint& p) const;    // north, east m
  GeoPoint to_geo(double north, double east) const;  // at the datum's altitude

 private:
  GeographicLib::LocalCartesian lc_;
  double alt_;
};

void localise(Mission& m, const GeoPoint& datum);

}  // namespace tiller::mission
