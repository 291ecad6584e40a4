// tiller-mission: publishes a path from a YAML or CSV mission file (TILLER_PATH), then the
// waypointing mode (TILLER_MODE) and an arm request (TILLER_ARM_REQUEST); repeats them every
// --repeat-s seconds until stopped (same path_id: the follower does not restart), or once.
// It has no config file (--config is refused): the mission file is --mission FILE.
#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>

#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(
      argc, argv,
      {"tiller-mission",
       "Publishes a mission's path, then the waypointing mode and an arm request.",
       "",
       {{"mission", "FILE", "mission file (.yaml or .csv)", "config/missions/default.yaml"},
        {"path-id", "N",
         "path id, a whole number >= 0 (default: the start time in us, so each run is a new path)",
         ""},
        {"repeat-s", "S", "repeat period, s >= 0; 0 = publish once and exit", "1"},
        {"no-arm", "", "do not send the arm request", ""}},
       false});  // no config file: the mission is --mission FILE

  return app::guarded_main("tiller-mission", [&] {
    // Numbers first, whole strings only; a bad value names the flag and what was expected.
    const double repeat =
        app::number_option(args, "repeat-s", 0, std::numeric_limits<double>::infinity(),
                           "a number of seconds >= 0 (0 = publish once)");
    std::int64_t id =
        args.get("path-id").empty()
            ? -1
            : app::integer_option(args, "path-id", 0, INT64_MAX, "a whole number >= 0 (int64)");
    const auto m = mission::load_mission_file(args.get("mission"));
    if (id < 0) id = wall_time_us();
    std::cout << "tiller-mission: " << m.name << ": " << m.waypoints.size()
              << " waypoints, path_id " << id << "\n";
    LiveExecutor ex(args.lcm_url, args.auth);
    mission::MissionNode node(m, id, from_seconds(repeat > 0 ? repeat : 1.0), !args.flag("no-arm"));
    if (repeat <= 0) {
      const auto p = mission::to_path(m, id, wall_time_us());
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(p.getEncodedSize()));
      p.encode(buf.data(), 0, static_cast<int>(buf.size()));
      ex.publish_raw("TILLER_PATH", buf.data(), static_cast<int>(buf.size()));
      controller_mode_t mode{};
      mode.utime = wall_time_us();
      mode.mode = controller_mode_t::WAYPOINTING;
      mode.is_translation = m.is_translation;
      mode.source = "mission";
      buf.resize(static_cast<std::size_t>(mode.getEncodedSize()));
      mode.encode(buf.data(), 0, static_cast<int>(buf.size()));
      ex.publish_raw("TILLER_MODE", buf.data(), static_cast<int>(buf.size()));
      if (!args.flag("no-arm")) {
        arm_request_t a{};
        a.utime = wall_time_us();
        a.arm = true;
        a.source = "mission";
        buf.resize(static_cast<std::size_t>(a.getEncodedSize()));
        a.encode(buf.data(), 0, static_cast<int>(buf.size()));
        ex.publish_raw("TILLER_ARM_REQUEST", buf.data(), static_cast<int>(buf.size()));
      }
      return 0;
    }
    ex.add(node);
    return ex.run();
  });
}
