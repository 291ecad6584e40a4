// tiller-score: scores a run from an LCM log: cross-track RMS / max, time to complete, final
// position and heading error, VRX wayfinding and station-keeping scores. The path is the first
// TILLER_PATH in the log (or --mission FILE); the pose is TILLER_GROUND_TRUTH when the log has
// it, else TILLER_ODOMETRY; completion is the first TILLER_PATH_PROGRESS saying complete.
// The scoring and the lines printed: lib/scores/log_scores.hpp (tiller-run prints the same).
#include <cstdio>

#include "mission/mission.hpp"
#include "runtime/app.hpp"
#include "runtime/log.hpp"
#include "scores/log_scores.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args =
      app::parse(argc, argv,
                 {"tiller-score",
                  "Scores a logged run (cross-track, time, final error, VRX scores).",
                  "",
                  {{"log", "FILE", "LCM log to score (required)", ""},
                   {"mission", "FILE", "mission file (default: the path in the log)", ""}},
                  false,    // no config file: --config refused
                  false});  // reads a log, opens no LCM: --lcm-url refused
  return app::guarded_main("tiller-score", [&] {
    if (args.get("log").empty()) throw std::runtime_error("--log FILE is required");
    std::vector<scores::Goal> path;
    if (!args.get("mission").empty()) {
      for (const auto& w : mission::load_mission_file(args.get("mission")).waypoints) {
        path.push_back({w.north, w.east, w.has_heading, w.heading});
      }
    }
    const auto events = read_log(args.get("log"), scores::kScoredChannels);
    scores::print_scores(scores::score_events(events, path), stdout);
    return 0;
  });
}
