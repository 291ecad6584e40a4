#include "scores/log_scores.hpp"

#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_t.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/angles.hpp"

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
  std::vector<Pose> estimate;  // TILLER_ODOMETRY when the pose is the truth
  // The same two at their messages' own time (utime: the instant each state is of), for the
  // estimation error: the logger's receive times differ between channels by the transport's
  // jitter, which the interpolation would turn into an error (1 mm at 1.5 m/s in a live run).
  std::vector<Pose> truth_at, estimate_at;
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
      if (!decode(e, o)) continue;
      r.poses.push_back({t, o.position[0], o.position[1], o.orientation[2]});
      if (have_truth)
        truth_at.push_back({to_seconds(o.utime), o.position[0], o.position[1], o.orientation[2]});
    } else if (have_truth && e.channel == "TILLER_ODOMETRY") {
      if (!decode(e, o)) continue;
      estimate.push_back({t, o.position[0], o.position[1], o.orientation[2]});
      estimate_at.push_back({to_seconds(o.utime), o.position[0], o.position[1], o.orientation[2]});
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
  const double end = complete_at ? *complete_at : 1e300;
  r.corners = corner_scores(r.poses, r.path, start, SteadyWindow{}.settle_s, end);
  r.samples = r.poses.size();
  if (have_truth && !estimate.empty()) {
    score_estimation(estimate_at, truth_at, r, start);
    // The follower followed the estimate: a one-point path from where the estimate was.
    r.estimate_path = path_as_followed(path, estimate, start);
    r.estimate_path_scores = score_path(estimate, r.estimate_path, start, complete_at);
    r.estimate_corners =
        corner_scores(estimate, r.estimate_path, start, SteadyWindow{}.settle_s, end);
    r.estimate_poses = std::move(estimate);
  }
  r.start = start;
  r.end = r.poses.back().t;
  if (r.path_scores.time_to_complete >= 0) {
    const double t0 = start + r.path_scores.time_to_complete;
    r.station_keeping = vrx_station_keeping(r.poses, r.path.back(), t0, r.end);
    r.station_keeping_s = r.end - t0;
  }
  return r;
}

void score_estimation(const std::vector<Pose>& estimate, const std::vector<Pose>& truth,
                      RunScores& r, double start) {
  double sp = 0, sh = 0, mp = 0, msp = 0, msh = 0;
  std::size_t n = 0, j = 0, mn = 0;
  for (const Pose& e : estimate) {
    if (truth.size() < 2 || e.t < truth.front().t || e.t > truth.back().t) continue;
    while (j + 2 < truth.size() && truth[j + 1].t < e.t) ++j;
    const Pose& a = truth[j];
    const Pose& b = truth[j + 1];
    const double f = b.t > a.t ? std::clamp((e.t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
    const double north = a.north + f * (b.north - a.north);
    const double east = a.east + f * (b.east - a.east);
    const double heading = wrap_pi(a.heading + f * wrap_pi(b.heading - a.heading));
    const double dp = std::hypot(e.north - north, e.east - east);
    const double dh = wrap_pi(e.heading - heading);
    sp += dp * dp;
    sh += dh * dh;
    mp = std::max(mp, dp);
    ++n;
    if (e.t >= start) {
      msp += dp * dp;
      msh += dh * dh;
      ++mn;
    }
  }
  r.estimation_samples = n;
  if (mn > 0) {
    r.mission_position_error_rms = std::sqrt(msp / static_cast<double>(mn));
    r.mission_heading_error_rms = std::sqrt(msh / static_cast<double>(mn));
  }
  if (n == 0) return;
  r.position_error_rms = std::sqrt(sp / static_cast<double>(n));
  r.position_error_max = mp;
  r.heading_error_rms = std::sqrt(sh / static_cast<double>(n));
}

void print_scores(const RunScores& r, std::FILE* out) {
  const auto& s = r.path_scores;
  std::fprintf(out, "pose from           %s (%zu samples)\n", r.pose_channel.c_str(), r.samples);
  std::fprintf(
      out, "waypoints           %zu (reached in order %d, missed %d)%s\n", r.path.size(),
      s.waypoints_reached, s.waypoints_missed,
      s.start_passed ? ", the start point passed: the vehicle began beside or past it" : "");
  if (s.time_to_complete >= 0)
    std::fprintf(out, "time to complete    %.1f s\n", s.time_to_complete);
  else
    std::fprintf(out, "time to complete    not completed\n");
  std::fprintf(out, "cross-track RMS     %.3f m (max %.3f m)\n", s.cross_track_rms,
               s.cross_track_max);
  const auto& c = r.corners;
  const SteadyWindow w;
  if (c.steady_cross_track_rms >= 0)
    std::fprintf(out,
                 "steady cross-track  %.4f m RMS (%.0f s after each waypoint's passage to %.0f m "
                 "before the next, %d samples)\n",
                 c.steady_cross_track_rms, w.settle_s, w.end_margin_m, c.steady_samples);
  else
    std::fprintf(out, "steady cross-track  - (no leg longer than %.0f s + %.0f m)\n", w.settle_s,
                 w.end_margin_m);
  if (!c.overshoot.empty()) {
    std::fprintf(out, "corner overshoot    %.3f m (largest of %zu corners:", c.max_overshoot,
                 c.overshoot.size());
    for (const double o : c.overshoot) std::fprintf(out, " %.2f", o);
    std::fprintf(out, ")\n");
  }
  if (c.weaving >= 0)
    std::fprintf(out, "weaving             %.4f rad/s RMS heading rate on the steady stretches\n",
                 c.weaving);
  std::fprintf(out, "final position err  %.3f m\n", s.final_position_error);
  if (s.final_heading_error >= 0)
    std::fprintf(out, "final heading err   %.3f rad\n", s.final_heading_error);
  std::fprintf(out, "VRX wayfinding      %.3f (mean over %d waypoints%s)\n", s.vrx_wayfinding,
               s.wayfinding_points, s.start_excluded ? ", the start point left out" : "");
  if (r.estimated()) {  // not on truth odometry
    std::fprintf(out,
                 "estimation error    position RMS %.3f m (max %.3f m), heading RMS %.2f deg "
                 "(TILLER_ODOMETRY vs truth, %zu samples); from the mission's start %.3f m, "
                 "%.2f deg\n",
                 r.position_error_rms, r.position_error_max, r.heading_error_rms * 180.0 / M_PI,
                 r.estimation_samples, r.mission_position_error_rms,
                 r.mission_heading_error_rms * 180.0 / M_PI);
  }
  if (r.estimated() && r.estimate_path_scores) {
    const auto& e = *r.estimate_path_scores;
    char time[32] = "not completed";
    if (e.time_to_complete >= 0) std::snprintf(time, sizeof time, "%.1f s", e.time_to_complete);
    std::fprintf(out,
                 "on the estimate     cross-track RMS %.3f m (max %.3f m), waypoints reached %d, "
                 "missed %d, time to complete %s (TILLER_ODOMETRY, %zu samples)\n",
                 e.cross_track_rms, e.cross_track_max, e.waypoints_reached, e.waypoints_missed,
                 time, r.estimate_poses.size());
  }
  if (s.time_to_complete >= 0) {
    std::fprintf(out, "VRX station keeping %.3f (from completion to the end of the log, %.0f s)\n",
                 r.station_keeping, r.station_keeping_s);
  }
}

}  // namespace tiller::scores
