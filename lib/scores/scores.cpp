#include "scores/scores.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.hpp"

namespace tiller::scores {

double vrx_error(double d, double h) {
  return d + std::pow(0.75, d) * h;
}

namespace {
// The nearest point of segment a-b to (n, e): its fraction t along it in [0, 1] and the distance.
struct Nearest {
  double t, distance;
};
Nearest nearest_on(const Goal& a, const Goal& b, double n, double e) {
  const double sn = b.north - a.north, se = b.east - a.east;
  const double l2 = sn * sn + se * se;
  const double t =
      std::clamp(l2 > 0 ? ((n - a.north) * sn + (e - a.east) * se) / l2 : 0.0, 0.0, 1.0);
  return {t, std::hypot(n - (a.north + t * sn), e - (a.east + t * se))};
}
}  // namespace

double distance_to_path(double n, double e, const std::vector<Goal>& path) {
  if (path.empty()) return 0;
  double best = std::hypot(n - path[0].north, e - path[0].east);
  for (std::size_t k = 1; k < path.size(); ++k)
    best = std::min(best, nearest_on(path[k - 1], path[k], n, e).distance);
  return best;
}

double depth_on_path(double n, double e, const std::vector<Goal>& path) {
  if (path.empty()) return 0;
  double best = std::numeric_limits<double>::infinity(), depth = path[0].depth;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const Nearest p = nearest_on(path[k - 1], path[k], n, e);
    if (p.distance < best) {
      best = p.distance;
      depth = path[k - 1].depth + p.t * (path[k].depth - path[k - 1].depth);
    }
  }
  return depth;
}

static double heading_error(const Goal& g, double heading) {
  return g.has_heading ? std::abs(angle_diff(g.heading, heading)) : 0.0;
}

PathScores score_path(const std::vector<Pose>& run, const std::vector<Goal>& path, double start,
                      std::optional<double> complete_at, double visit_radius) {
  PathScores s;
  if (path.empty() || run.empty()) return s;
  const Pose* first = nullptr;  // the pose at the start
  for (const auto& p : run) {
    if (p.t >= start) {
      first = &p;
      break;
    }
  }
  // Waypoints reached in order; a start point the vehicle began beside or past along the first
  // segment is passed, as the follower passes it (see scores.hpp).
  if (path.size() > 1 && first != nullptr) {
    const double dn = first->north - path[0].north, de = first->east - path[0].east;
    const double sn = path[1].north - path[0].north, se = path[1].east - path[0].east;
    s.start_passed = std::hypot(dn, de) >= visit_radius && sn * dn + se * de >= 0;
  }
  std::size_t next = s.start_passed ? 1 : 0;
  double reached_last_at = -1;
  std::vector<double> best_e(path.size(), std::numeric_limits<double>::infinity());
  for (const auto& p : run) {
    if (p.t < start) continue;
    for (std::size_t k = 0; k < path.size(); ++k) {
      const double d = std::hypot(p.north - path[k].north, p.east - path[k].east);
      best_e[k] = std::min(best_e[k], vrx_error(d, heading_error(path[k], p.heading)));
    }
    while (next < path.size() &&
           std::hypot(p.north - path[next].north, p.east - path[next].east) < visit_radius) {
      if (next + 1 == path.size()) reached_last_at = p.t;
      ++next;
    }
  }
  s.waypoints_reached = static_cast<int>(next);
  s.waypoints_missed = static_cast<int>(path.size() - next);
  const double end =
      complete_at ? *complete_at : (reached_last_at >= 0 ? reached_last_at : run.back().t);
  if (complete_at)
    s.time_to_complete = *complete_at - start;
  else if (reached_last_at >= 0)
    s.time_to_complete = reached_last_at - start;
  double sum = 0;
  int n = 0;
  for (const auto& p : run) {
    if (p.t < start || p.t > end) continue;
    const double d = distance_to_path(p.north, p.east, path);
    sum += d * d;
    s.cross_track_max = std::max(s.cross_track_max, d);
    ++n;
  }
  s.cross_track_rms = n ? std::sqrt(sum / n) : 0;
  const auto& g = path.back();
  s.final_position_error = std::hypot(run.back().north - g.north, run.back().east - g.east);
  s.final_heading_error = g.has_heading ? std::abs(angle_diff(g.heading, run.back().heading)) : -1;
  // Wayfinding: the task's waypoints, without the start (see scores.hpp).
  s.start_excluded = path.size() > 1 && first != nullptr &&
                     (s.start_passed || std::hypot(first->north - path[0].north,
                                                   first->east - path[0].east) < visit_radius);
  double w = 0;
  for (std::size_t k = s.start_excluded ? 1 : 0; k < best_e.size(); ++k) {
    w += best_e[k];
    ++s.wayfinding_points;
  }
  s.vrx_wayfinding = w / static_cast<double>(s.wayfinding_points);
  return s;
}

std::vector<Goal> path_as_followed(const std::vector<Goal>& path, const std::vector<Pose>& run,
                                   double start, double min_segment_length) {
  if (path.size() != 1) return path;
  for (const auto& p : run) {
    if (p.t < start) continue;
    if (std::hypot(p.north - path[0].north, p.east - path[0].east) < min_segment_length) break;
    return {Goal{p.north, p.east, false, 0}, path[0]};
  }
  return path;
}

double vrx_station_keeping(const std::vector<Pose>& run, const Goal& goal, double t0, double t1) {
  double sum = 0;
  int n = 0;
  for (const auto& p : run) {
    if (p.t < t0 || p.t > t1) continue;
    sum += vrx_error(std::hypot(p.north - goal.north, p.east - goal.east),
                     heading_error(goal, p.heading));
    ++n;
  }
  return n ? sum / n : -1;
}

double max_distance(const std::vector<Pose>& run, const Goal& goal, double t0, double t1) {
  double m = 0;
  for (const auto& p : run) {
    if (p.t < t0 || p.t > t1) continue;
    m = std::max(m, std::hypot(p.north - goal.north, p.east - goal.east));
  }
  return m;
}

}  // namespace tiller::scores
