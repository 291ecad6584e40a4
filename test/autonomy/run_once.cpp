// Development helper: runs one mission and prints the result (not a test).
#include <cstdio>
#include <cstdlib>

#include <string>
#include "harness.hpp"
#include "plants.hpp"

int main(int argc, char** argv) {
  tiller::test::RunConfig c;
  if (argc > 1) c.mission_file = argv[1];
  if (argc > 2) c.guidance_file = argv[2];
  if (argc > 3) c.control_file = argv[3];
  if (argc > 4) c.current_speed = std::atof(argv[4]);
  const char* plant = std::getenv("PLANT");
  for (const auto& p : tiller::test::plants()) {
    if (plant && p.name == plant) {
      c.make_plant = p.make;
      c.pose_channel = p.pose_channel;
      if (argc <= 3) c.control_file = p.control_file;
      if (argc <= 2) c.guidance_file = p.guidance_file;
    }
  }
  const auto r = tiller::test::run_mission(c);
  std::printf(
      "completed %d at %.1f s, skipped %d, missed %d, xte rms %.3f max %.3f, final %.3f, "
      "station vrx %.3f max d %.3f held %.0f, switches %d jump %.1f N, maxF %.1f, wayfinding %.3f, "
      "wall %.3f s\n",
      r.completed, r.completed_at, r.skipped, r.path.waypoints_missed, r.path.cross_track_rms,
      r.path.cross_track_max, r.path.final_position_error, r.station_vrx, r.station_max_distance,
      r.held_s, r.switches, r.max_switch_jump, r.max_force, r.path.vrx_wayfinding, r.wall_s);
  if (argc > 5) {
    for (std::size_t k = 0; k < r.poses.size(); k += 20) {
      std::printf("%.1f %.2f %.2f %.2f\n", r.poses[k].t, r.poses[k].north, r.poses[k].east,
                  r.poses[k].heading);
    }
  }
}
