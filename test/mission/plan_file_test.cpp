// QGroundControl .plan files and our YAML items into the one mission model: every item type, the
// geodesy against a hand-computed figure, and each refusal naming the item and the command.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "mission/fence.hpp"
#include "mission/geo.hpp"
#include "mission/mission.hpp"
#include "mission/plan_file.hpp"

namespace tiller::mission {
namespace {

std::string src(const std::string& rel) {
  return std::string(TILLER_SOURCE_DIR) + "/" + rel;
}

std::string write_tmp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// The error load_mission_file throws for `path` ("" if none).
std::string refusal(const std::string& path) {
  try {
    load_mission_file(path);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "";
}

TEST(Geodesy, AMilliDegreeOfLatitudeIsTheMeridianArc) {
  // Meridian arc per degree at latitude p: 111132.954 - 559.822 cos 2p + 1.175 cos 4p m
  // (WGS84); at 63.44 deg: 111468.5 m, so 0.001 deg north is 111.47 m.
  const LocalFrame f({63.44, 10.4, 0});
  const auto p = f.to_local({63.441, 10.4, 0});
  EXPECT_NEAR(p.north, 111.47, 0.02);
  EXPECT_NEAR(p.east, 0, 1e-6);
  // A parallel degree there: 111412.84 cos p - 93.5 cos 3p = 49812.7 + 92.0 = 49904.7 m; 0.001
  // deg east 49.905 m (the tangent plane's east differs from the arc by millimetres at 50 m).
  const auto q = f.to_local({63.44, 10.401, 0});
  EXPECT_NEAR(q.east, 49.905, 0.01);
  const auto back = f.to_geo(q.north, q.east);
  EXPECT_NEAR(back.lat_deg, 63.44, 1e-10);
  EXPECT_NEAR(back.lon_deg, 10.401, 1e-10);
}

TEST(PlanFile, TheHarbourPlanAsQGroundControlWroteIt) {
  const auto m = load_mission_file(src("config/missions/harbour.plan"));
  ASSERT_EQ(m.items.size(), 7u);
  const ItemKind kinds[] = {ItemKind::kSpeed,     ItemKind::kWaypoint, ItemKind::kWaypoint,
                            ItemKind::kLoiter,    ItemKind::kSpeed,    ItemKind::kWaypoint,
                            ItemKind::kReturnHome};
  const int commands[] = {178, 16, 16, 19, 178, 16, 20};
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(m.items[k].kind, kinds[k]) << k;
    EXPECT_EQ(m.items[k].command, commands[k]) << k;
    EXPECT_EQ(m.items[k].index, k);
  }
  EXPECT_DOUBLE_EQ(m.items[0].speed, 1.0);
  EXPECT_DOUBLE_EQ(m.items[4].speed, 1.5);
  EXPECT_DOUBLE_EQ(m.items[3].loiter_s, 10);
  // The fixture's points were placed with the arc lengths above: within 2 cm of the metres.
  const double expect[][2] = {{30, 0}, {30, 25}, {10, 25}, {10, 5}};
  ASSERT_EQ(m.waypoints.size(), 5u);  // and home, where the return goes
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(m.waypoints[k].north, expect[k][0], 0.02) << k;
    EXPECT_NEAR(m.waypoints[k].east, expect[k][1], 0.02) << k;
  }
  ASSERT_TRUE(m.home && m.datum);
  EXPECT_NEAR(m.home_point.north, 0, 1e-9);
  ASSERT_TRUE(m.start);
  EXPECT_NEAR(m.start->east, 0, 1e-9);
  ASSERT_EQ(m.fence.size(), 1u);
  EXPECT_TRUE(m.fence[0].inclusion);
  ASSERT_EQ(m.fence[0].polygon.size(), 4u);
  EXPECT_NEAR(m.fence[0].polygon[2].north, 45, 0.02);
  EXPECT_NEAR(m.fence[0].polygon[2].east, 40, 0.02);
}

TEST(PlanFile, ADatumOtherThanHomeMovesEveryPoint) {
  const LocalFrame home({63.44, 10.4, 2});
  const GeoPoint datum = home.to_geo(-100, 50);  // 100 m south, 50 m east of home
  const auto m = load_mission_file(src("config/missions/harbour.plan"), datum);
  EXPECT_NEAR(m.home_point.north, 100, 0.01);
  EXPECT_NEAR(m.home_point.east, -50, 0.01);
  EXPECT_NEAR(m.waypoints[0].north, 130, 0.03);
}

TEST(PlanFile, JumpLandRallyAndDefaultSpeed) {
  const auto m = load_mission_file(src("test/mission/jump_land.plan"));
  ASSERT_EQ(m.items.size(), 5u);
  EXPECT_EQ(m.items[2].kind, ItemKind::kJump);
  EXPECT_EQ(m.items[2].jump_to, 0);  // doJumpId 1
  EXPECT_EQ(m.items[2].repeat, 2);
  EXPECT_EQ(m.items[3].kind, ItemKind::kSpeed);
  EXPECT_DOUBLE_EQ(m.items[3].speed, 0);  // -2: back to the default
  EXPECT_EQ(m.items[4].kind, ItemKind::kStop);
  EXPECT_TRUE(m.items[4].has_point);
  EXPECT_NEAR(m.items[4].point.east, 10, 0.02);
  ASSERT_EQ(m.rally.size(), 1u);
  EXPECT_NEAR(m.rally[0].north, 5, 0.02);
  EXPECT_NEAR(m.rally[0].east, -5, 0.02);
}

TEST(PlanFile, LoiterUnlimitedAndAnInclusionCircle) {
  const auto m = load_mission_file(src("test/mission/loiter_unlimited.plan"));
  ASSERT_EQ(m.items.size(), 2u);
  EXPECT_EQ(m.items[1].kind, ItemKind::kLoiter);
  EXPECT_LT(m.items[1].loiter_s, 0);
  ASSERT_EQ(m.fence.size(), 2u);
  EXPECT_TRUE(m.fence[1].circle);
  EXPECT_DOUBLE_EQ(m.fence[1].radius_m, 60);
  EXPECT_EQ(fence_breach(m.fence, 10, 10), -1);
  EXPECT_EQ(fence_breach(m.fence, 44, 39), -1);     // 59.4 m from the circle's centre
  EXPECT_EQ(fence_breach(m.fence, 44.9, 39.9), 1);  // in the polygon, 60.07 m out: the circle
  EXPECT_EQ(fence_breach(m.fence, 46, 0), 0);
}

TEST(PlanFile, RefusalsNameTheItemAndTheCommand) {
  const std::string takeoff = refusal(src("test/mission/takeoff.plan"));
  EXPECT_NE(takeoff.find("item 0 (command 22)"), std::string::npos) << takeoff;
  EXPECT_NE(takeoff.find("take-off"), std::string::npos) << takeoff;
  const std::string out = refusal(src("test/mission/outside_fence.plan"));
  EXPECT_NE(out.find("item 1 (command 16)"), std::string::npos) << out;
  EXPECT_NE(out.find("outside the fence (inclusion polygon 0)"), std::string::npos) << out;
  const std::string in = refusal(src("test/mission/exclusion.plan"));
  EXPECT_NE(in.find("item 1 (command 16)"), std::string::npos) << in;
  EXPECT_NE(in.find("inside the fence (exclusion circle 0)"), std::string::npos) << in;
  const std::string terrain = refusal(src("test/mission/terrain_frame.plan"));
  EXPECT_NE(terrain.find("item 1 (command 16)"), std::string::npos) << terrain;
  EXPECT_NE(terrain.find("frame 10"), std::string::npos) << terrain;
  const std::string unknown = refusal(src("test/mission/unknown_command.plan"));
  EXPECT_NE(unknown.find("item 1 (command 115)"), std::string::npos) << unknown;
  const std::string servo = refusal(src("test/mission/servo.plan"));
  EXPECT_NE(servo.find("item 1 (command 183)"), std::string::npos) << servo;
  EXPECT_NE(servo.find("no servo or relay outputs"), std::string::npos) << servo;
}

// A plan around one complex item: QGroundControl's survey (or corridor scan) with its generated
// items: waypoints and the camera trigger distance (206, ignored: no camera).
std::string complex_plan(const std::string& type, bool with_items) {
  const std::string items = R"([
    {"autoContinue": true, "command": 16, "doJumpId": 1, "frame": 3,
     "params": [0, 0, 0, null, 63.4401, 10.4001, 0], "type": "SimpleItem"},
    {"autoContinue": true, "command": 206, "doJumpId": 2, "frame": 2,
     "params": [25, 0, 1, 0, 0, 0, 0], "type": "SimpleItem"},
    {"autoContinue": true, "command": 16, "doJumpId": 3, "frame": 3,
     "params": [0, 0, 0, null, 63.4402, 10.4001, 0], "type": "SimpleItem"},
    {"autoContinue": true, "command": 206, "doJumpId": 4, "frame": 2,
     "params": [0, 0, 1, 0, 0, 0, 0], "type": "SimpleItem"}])";
  return std::string(R"({"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
    "geoFence": {"circles": [], "polygons": [], "version": 2},
    "rallyPoints": {"points": [], "version": 2},
    "mission": {"version": 2, "firmwareType": 3, "vehicleType": 11, "cruiseSpeed": 1.5,
      "hoverSpeed": 1, "globalPlanAltitudeMode": 1, "plannedHomePosition": [63.44, 10.4, 2],
      "items": [{"type": "ComplexItem", "complexItemType": ")") +
         type + R"(", "version": 5, "angle": 0,
        "polygon": [[63.4401, 10.4], [63.4401, 10.4002], [63.4402, 10.4002], [63.4402, 10.4]],
        "TransectStyleComplexItem": {"TurnAroundDistance": 10, "version": 1)" +
         (with_items ? std::string(", \"Items\": ") + items : std::string()) +
         R"(}},
      {"autoContinue": true, "command": 20, "doJumpId": 5, "frame": 2,
       "params": [0, 0, 0, 0, 0, 0, 0], "type": "SimpleItem"}]}})";
}

TEST(PlanFile, SurveyAndCorridorScanFlyTheirGeneratedItems) {
  for (const char* type : {"survey", "CorridorScan"}) {
    const auto m = load_mission_file(write_tmp("complex.plan", complex_plan(type, true)));
    ASSERT_EQ(m.items.size(), 3u) << type;  // two waypoints (the 206s ignored), the return
    EXPECT_EQ(m.items[0].index, 0);
    EXPECT_EQ(m.items[1].index, 0);
    EXPECT_EQ(m.items[2].kind, ItemKind::kReturnHome);
    EXPECT_EQ(m.items[2].index, 1);
    EXPECT_NEAR(m.items[1].point.north - m.items[0].point.north, 11.147, 0.01);
  }
  const std::string none = refusal(write_tmp("complex.plan", complex_plan("survey", false)));
  EXPECT_NE(none.find("item 0 (survey)"), std::string::npos) << none;
  const std::string other = refusal(write_tmp("complex.plan", complex_plan("StructureScan", true)));
  EXPECT_NE(other.find("item 0: complex item 'StructureScan'"), std::string::npos) << other;
}

TEST(PlanFile, NotAPlan) {
  EXPECT_NE(refusal(write_tmp("bad.plan", "{\"fileType\": \"Plan\", ")).find("not JSON"),
            std::string::npos);
  EXPECT_NE(refusal(write_tmp("bad.plan", "{\"fileType\": \"GeoFence\", \"version\": 1}"))
                .find("fileType"),
            std::string::npos);
}

TEST(YamlItems, LocalMetresWithAFenceAndARally) {
  const auto m = load_mission_file(write_tmp("items.yaml", R"(name: items
start: {north: 0, east: 0}
items:
  - {do: speed, speed: 0.8}
  - {do: waypoint, north: 10, east: 0}
  - [10, 10]
  - {do: loiter, north: 0, east: 10, time_s: 5}
  - {do: jump, to: 1, repeat: 1}
  - {do: return_home}
fence:
  action: return
  inclusion: [[[-5, -5], [-5, 20], [20, 20], [20, -5]]]
  exclusion: [{circle: [5, 5], radius_m: 2}]
rally: [[2, -2]]
return_end: stop
)"));
  ASSERT_EQ(m.items.size(), 6u);
  EXPECT_FALSE(m.datum);
  EXPECT_EQ(m.items[2].kind, ItemKind::kWaypoint);
  EXPECT_DOUBLE_EQ(m.items[2].point.east, 10);
  EXPECT_EQ(m.items[4].jump_to, 1);
  EXPECT_EQ(m.fence_action, FenceAction::kReturn);
  EXPECT_EQ(m.return_end, ReturnEnd::kStop);
  ASSERT_EQ(m.fence.size(), 2u);
  EXPECT_EQ(fence_breach(m.fence, 5, 6), 1);  // in the exclusion circle
  EXPECT_EQ(fence_breach(m.fence, 21, 0), 0);
  EXPECT_EQ(fence_breach(m.fence, -5, 0), -1);  // on the edge counts as inside
  EXPECT_EQ(m.waypoints.size(), 3u);
}

TEST(YamlItems, GeodeticNeedsAHomeAndJumpsMustLand) {
  const std::string no_home =
      refusal(write_tmp("geo.yaml", "items:\n  - {do: waypoint, lat: 63.44, lon: 10.4}\n"));
  EXPECT_NE(no_home.find("expected a home position"), std::string::npos) << no_home;
  const auto g = load_mission_file(write_tmp(
      "geo.yaml",
      "home: {lat: 63.44, lon: 10.4}\nitems:\n  - {do: waypoint, lat: 63.441, lon: 10.4}\n"));
  EXPECT_NEAR(g.waypoints[0].north, 111.47, 0.02);
  const std::string loop =
      refusal(write_tmp("loop.yaml",
                        "items:\n  - [1, 1]\n  - {do: speed, speed: 1}\n  - {do: jump, "
                        "to: 1, repeat: -1}\n"));
  EXPECT_NE(loop.find("item 2: the jump passes no point"), std::string::npos) << loop;
  const std::string far =
      refusal(write_tmp("far.yaml", "items:\n  - [1, 1]\n  - {do: jump, to: 7, repeat: 1}\n"));
  EXPECT_NE(far.find("item 1: jump to an item that is not in the mission"), std::string::npos)
      << far;
  const std::string fence = refusal(write_tmp(
      "fence.yaml", "items:\n  - [30, 1]\nfence: {inclusion: [[[0, 0], [0, 20], [20, 20]]]}\n"));
  EXPECT_NE(fence.find("item 0: the point (30.0 m north, 1.0 m east) is outside the fence"),
            std::string::npos)
      << fence;
}

// Depth, an ROV's (NED down, m below the surface), in both formats and on the path.
namespace depth {

std::string plan(int vehicle_type, double alt1, double alt2) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                R"({"fileType": "Plan", "version": 1, "geoFence": {}, "rallyPoints": {},
    "mission": {"version": 2, "vehicleType": %d, "plannedHomePosition": [63.44, 10.4, 0],
      "items": [
        {"type": "SimpleItem", "command": 16, "frame": 3, "doJumpId": 1,
         "params": [0, 0, 0, null, 63.4401, 10.4, %g]},
        {"type": "SimpleItem", "command": 16, "frame": 3, "doJumpId": 2,
         "params": [0, 0, 0, null, 63.4402, 10.4, %g]}]}})",
                vehicle_type, alt1, alt2);
  return buf;
}

}  // namespace depth

TEST(MissionDepth, YamlPointsKeepTheDepthBeforeThemAndThePathCarriesIt) {
  const auto m = load_mission_file(write_tmp("depth.yaml", R"(name: d
depth: 2
waypoints:
  - [0, 0]
  - {north: 5, east: 0, depth: 3.5}
  - [10, 0]
  - {north: 10, east: 5, heading_deg: 90, depth: 0}
)"));
  ASSERT_EQ(m.waypoints.size(), 4u);
  EXPECT_EQ(m.waypoints[0].depth, 2.0);  // the mission's
  EXPECT_EQ(m.waypoints[1].depth, 3.5);  // its own
  EXPECT_EQ(m.waypoints[2].depth, 3.5);  // the one before
  EXPECT_EQ(m.waypoints[3].depth, 0.0);  // back at the surface
  const path_t p = to_path(m, 7, 0);
  EXPECT_EQ(p.waypoints[1].position[2], 3.5);
  EXPECT_EQ(p.waypoints[2].position[2], 3.5);
  // A boat's mission names no depth: every point at 0.
  const auto b = load_mission_file(src("config/missions/default.yaml"));
  for (const auto& w : b.waypoints) EXPECT_EQ(w.depth, 0.0);
  // Out of range: the key, the file and the range.
  const std::string e =
      refusal(write_tmp("bad_depth.yaml", "waypoints:\n  - {north: 1, east: 2, depth: -1}\n"));
  EXPECT_NE(e.find("bad_depth.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("depth"), std::string::npos) << e;
  EXPECT_NE(e.find("11000"), std::string::npos) << e;
}

TEST(MissionDepth, ASubmarinesPlanAltitudeIsMinusItsDepth) {
  // vehicleType 12 (MAV_TYPE_SUBMARINE): -2.5 m altitude is 2.5 m deep.
  auto m = parse_plan(depth::plan(12, -2.5, -4), "sub.plan");
  finish_items(m, "sub.plan", std::nullopt);
  ASSERT_EQ(m.waypoints.size(), 2u);
  EXPECT_EQ(m.waypoints[0].depth, 2.5);
  EXPECT_EQ(m.waypoints[1].depth, 4.0);
  EXPECT_NEAR(m.waypoints[1].north, 22.3, 0.1);  // 0.0002 deg of latitude, about 22.3 m
  // A boat's (vehicleType 10, a surface boat) altitude is ignored.
  auto b = parse_plan(depth::plan(10, 5, 7), "boat.plan");
  finish_items(b, "boat.plan", std::nullopt);
  EXPECT_EQ(b.waypoints[0].depth, 0.0);
  // A submarine above the water: refused, naming the item.
  try {
    parse_plan(depth::plan(12, -1, 3), "up.plan");
    ADD_FAILURE() << "a positive altitude for a submarine was taken";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("up.plan: item 1 (command 16)"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("minus its depth"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tiller::mission
