// Scores of a run, from the vehicle's pose over time (world NED, m; headings rad NED).
// Lower is better for every number.
//   * cross-track RMS and max (m): distance from the vehicle to the path polyline, from the
//     start time until the path is complete (or the end of the samples);
//   * time to complete (s), waypoints reached in order within visit_radius, and missed;
//   * final position error (m) and heading error (rad, -1 if the goal has no heading);
//   * VRX station keeping: mean over a window of E = d + 0.75^d * h, with d the distance to the
//     goal (m) and h the heading error in [0, pi] (0 when the goal has no heading);
//   * VRX wayfinding: for each waypoint of the task the minimum E over the run, averaged over
//     those waypoints. As in VRX, where the vehicle starts is not one of the task's waypoints:
//     a first point within visit_radius of the pose at `start` (a path that begins where the
//     boat is, as every mission in config/missions does) is left out of the mean; it would score
//     about 0 and bias the mean low.
//   * A vehicle that begins away from the path's first point (a real vehicle starts where it
//     is; in a current it drifts while the mission waits for the estimate: mission/
//     start_gate.hpp) but beside or past it along the first segment ((p1 - p0).(x - p0) >= 0,
//     farther than visit_radius) is not steered back to it by the follower, which joins the
//     first segment where it is: that start point counts as reached (start_passed) and is left
//     out of the wayfinding mean. Behind it, the first point is scored as any other.
// A one-point path is followed from where the vehicle is (guidance/path_follower.hpp): score it
// as followed with path_as_followed().
#pragma once

#include <optional>
#include <vector>

namespace tiller::scores {

struct Pose {
  double t = 0;  // s
  double north = 0, east = 0;
  double heading = 0;  // rad
};

struct Goal {
  double north = 0, east = 0;
  bool has_heading = false;
  double heading = 0;
  double depth = 0;  // m, NED down (an ROV's path; 0 for a boat's)
};

struct PathScores {
  double cross_track_rms = 0, cross_track_max = 0;  // m
  double time_to_complete = -1;                     // s from start; -1: not completed
  int waypoints_reached = 0, waypoints_missed = 0;
  double final_position_error = 0;  // m at the last sample
  double final_heading_error = -1;  // rad; -1: the goal has no heading
  double vrx_wayfinding = 0;
  int wayfinding_points = 0;    // waypoints in the wayfinding mean
  bool start_excluded = false;  // the first point was where the vehicle started: not scored
  bool start_passed = false;    // ... or the vehicle began beside or past it: counted reached
};

// The path as the follower follows it: a one-point path gets the vehicle's position at `start`
// (the first pose at or after it) prepended, unless the vehicle is already at the point
// (within min_segment_length); any other path is returned as it is.
std::vector<Goal> path_as_followed(const std::vector<Goal>& path, const std::vector<Pose>& run,
                                   double start, double min_segment_length = 0.05);

// E = d + 0.75^d * h (VRX).
double vrx_error(double d, double h);
// Distance from a point to a polyline (a single point: distance to it).
double distance_to_path(double n, double e, const std::vector<Goal>& path);
// The path's depth (m) at the point of its horizontally nearest segment to (n, e), interpolated
// between the segment's two depths; a one-point path's own. tiller-run's ROV depth error.
double depth_on_path(double n, double e, const std::vector<Goal>& path);

// `start`: time the path was given; `complete_at`: when the follower reported it complete (if
// known; otherwise the time the last waypoint was reached in order).
PathScores score_path(const std::vector<Pose>& run, const std::vector<Goal>& path, double start,
                      std::optional<double> complete_at = std::nullopt, double visit_radius = 1.0);

// Mean of E over samples with t in [t0, t1]; -1 if there are none.
double vrx_station_keeping(const std::vector<Pose>& run, const Goal& goal, double t0, double t1);
// Largest distance from the goal over samples with t in [t0, t1].
double max_distance(const std::vector<Pose>& run, const Goal& goal, double t0, double t1);

}  // namespace tiller::scores
