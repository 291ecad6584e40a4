#include "scores/log_scores.hpp"

#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <stdexcept>

namespace tiller::scores {

RunScores score_events(const std::vector<Event>& events, const std::vector<Goal>& mission_path) {
  RunScores r;
  std::vector<Goal> path = mission_path;
  double start = -1;
  std::int64_t path_id = -1;
  bool have_truth = false;
  for (const auto& e : events) have_truth |= e.channel == "TILLER_GROUND_TRUTH";
  r.pose_channel = have_truth ? "TILLER_GROUND_TRUTH" : "TILLER_ODOMETRY";
  std::optional<double> complete_at;
  path_t p;
  odometry_t o;
  path_progress_t pr;
  for (const auto& e : events) {
    const double t = to_seconds(e.time);
    if (e.channel == "TILLER_PATH" && start < 0) {
      if (!decode(e, p)) continue;
      start = t;
      path_id = p.path_id;
      if (path.empty()) {
        for (const auto& w : p.waypoints)
          path.push_back({w.position[0], w.position[1], w.has_heading != 0, w.heading});
      }
    } else if (e.channel == r.pose_channel) {
      if (decode(e, o)) r.poses.push_back({t, o.position[0], o.position[1], o.orientation[2]});
    } else if (e.channel == "TILLER_PATH_PROGRESS" && !complete_at) {
      if (decode(e, pr) && pr.complete && pr.path_id == path_id) complete_at = t;
    }
  }
  if (path.empty()) throw std::runtime_error("no TILLER_PATH in the log and no --mission");
  if (r.poses.empty()) throw std::runtime_error("no " + r.pose_channel + " in the log");
  if (start < 0) start = r.poses.front().t;
  // A one-point path is followed from where the boat was: score it that way (else the
  // cross-track would be the distance to the goal).
  r.path = path_as_followed(path, r.poses, start);
  r.path_scores = score_path(r.poses, r.path, start, complete_at);
  r.samples = r.poses.size();
  r.start = start;
  r.end = r.poses.back().t;
  if (r.path_scores.time_to_complete >= 0) {
    const double t0 = start + r.path_scores.time_to_complete;
    r.station_keeping = vrx_station_keeping(r.poses, r.path.back(), t0, r.end);
    r.station_keeping_s = r.end - t0;
  }
  return r;
}

void print_scores(const RunScores& r, std::FILE* out) {
  const auto& s = r.path_scores;
  std::fprintf(out, "pose from           %s (%zu samples)\n", r.pose_channel.c_str(), r.samples);
  std::fprintf(out, "waypoints           %zu (reached in order %d, missed %d)\n", r.path.size(),
               s.waypoints_reached, s.waypoints_missed);
  if (s.time_to_complete >= 0)
    std::fprintf(out, "time to complete    %.1f s\n", s.time_to_complete);
  else
    std::fprintf(out, "time to complete    not completed\n");
  std::fprintf(out, "cross-track RMS     %.3f m (max %.3f m)\n", s.cross_track_rms,
               s.cross_track_max);
  std::fprintf(out, "final position err  %.3f m\n", s.final_position_error);
  if (s.final_heading_error >= 0)
    std::fprintf(out, "final heading err   %.3f rad\n", s.final_heading_error);
  std::fprintf(out, "VRX wayfinding      %.3f (mean over %d waypoints%s)\n", s.vrx_wayfinding,
               s.wayfinding_points, s.start_excluded ? ", the start point left out" : "");
  if (s.time_to_complete >= 0) {
    std::fprintf(out, "VRX station keeping %.3f (from completion to the end of the log, %.0f s)\n",
                 r.station_keeping, r.station_keeping_s);
  }
}

}  // namespace tiller::scores
