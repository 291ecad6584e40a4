// tiller-score: scores a run from an LCM log: cross-track RMS / max, time to complete, final
// position and heading error, VRX wayfinding and station-keeping scores. The path is the first
// TILLER_PATH in the log (or --mission FILE); the pose is TILLER_GROUND_TRUTH when the log has
// it, else TILLER_ODOMETRY; completion is the first TILLER_PATH_PROGRESS saying complete.
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <cstdio>
#include <optional>

#include "mission/mission.hpp"
#include "runtime/app.hpp"
#include "runtime/log.hpp"
#include "scores/scores.hpp"

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
    const auto events =
        read_log(args.get("log"), "TILLER_(GROUND_TRUTH|ODOMETRY|PATH|PATH_PROGRESS)");
    std::vector<scores::Goal> path;
    double start = -1;
    std::int64_t path_id = -1;
    if (!args.get("mission").empty()) {
      for (const auto& w : mission::load_mission_file(args.get("mission")).waypoints) {
        path.push_back({w.north, w.east, w.has_heading, w.heading});
      }
    }
    bool have_truth = false;
    for (const auto& e : events) have_truth |= e.channel == "TILLER_GROUND_TRUTH";
    const std::string pose_ch = have_truth ? "TILLER_GROUND_TRUTH" : "TILLER_ODOMETRY";
    std::vector<scores::Pose> run;
    std::optional<double> complete_at;
    for (const auto& e : events) {
      const double t = to_seconds(e.time);
      if (e.channel == "TILLER_PATH" && start < 0) {
        path_t p;
        if (!decode(e, p)) continue;
        start = t;
        path_id = p.path_id;
        if (path.empty()) {
          for (const auto& w : p.waypoints)
            path.push_back({w.position[0], w.position[1], w.has_heading != 0, w.heading});
        }
      } else if (e.channel == pose_ch) {
        odometry_t o;
        if (decode(e, o)) run.push_back({t, o.position[0], o.position[1], o.orientation[2]});
      } else if (e.channel == "TILLER_PATH_PROGRESS" && !complete_at) {
        path_progress_t p;
        if (decode(e, p) && p.complete && p.path_id == path_id) complete_at = t;
      }
    }
    if (path.empty()) throw std::runtime_error("no TILLER_PATH in the log and no --mission");
    if (run.empty()) throw std::runtime_error("no " + pose_ch + " in the log");
    if (start < 0) start = run.front().t;
    // A one-point path is followed from where the boat was: score it that way (else the
    // cross-track would be the distance to the goal).
    path = scores::path_as_followed(path, run, start);
    const auto s = scores::score_path(run, path, start, complete_at);
    const auto& g = path.back();
    std::printf("pose from           %s (%zu samples)\n", pose_ch.c_str(), run.size());
    std::printf("waypoints           %zu (reached in order %d, missed %d)\n", path.size(),
                s.waypoints_reached, s.waypoints_missed);
    if (s.time_to_complete >= 0)
      std::printf("time to complete    %.1f s\n", s.time_to_complete);
    else
      std::printf("time to complete    not completed\n");
    std::printf("cross-track RMS     %.3f m (max %.3f m)\n", s.cross_track_rms, s.cross_track_max);
    std::printf("final position err  %.3f m\n", s.final_position_error);
    if (s.final_heading_error >= 0)
      std::printf("final heading err   %.3f rad\n", s.final_heading_error);
    std::printf("VRX wayfinding      %.3f (mean over %d waypoints%s)\n", s.vrx_wayfinding,
                s.wayfinding_points, s.start_excluded ? ", the start point left out" : "");
    if (s.time_to_complete >= 0) {
      const double t0 = start + s.time_to_complete;
      std::printf("VRX station keeping %.3f (from completion to the end of the log, %.0f s)\n",
                  scores::vrx_station_keeping(run, g, t0, run.back().t), run.back().t - t0);
    }
    return 0;
  });
}
