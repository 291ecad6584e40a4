// The data of a run plot, extracted from a log: trajectory seen from above (ground truth when
// the simulator logged it, else odometry), the path's waypoints, speed over ground against the
// velocity setpoint, heading against the target heading, cross-track error and distance to goal
// (each on its own axis), thruster commands and saturation, and a mark for each waypoint passed
// and for the mission complete (from TILLER_PATH_PROGRESS). A waypoint passed counts as reached
// when the trajectory came within kPlotVisitRadius of it between the follower's previous
// switch and its next one (tiller-score's visit radius), else it is drawn as missed, with its
// closest approach. Written as CSV files plus a gnuplot
// script that draws them into one PNG (tiller-plot). Times in s since the log's first event;
// headings in degrees for people, unwrapped (a turn through south is a continuous line, not a
// jump from +180 to -180).
#pragma once

#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

// m: scores::score_path's visit radius (lib/scores/scores.hpp), the follower's acceptance_radius.
inline constexpr double kPlotVisitRadius = 1.0;

// A waypoint passed (TILLER_PATH_PROGRESS.segment moved on to it) or the mission complete
// (complete became true), where the vehicle was then (the latest trajectory point).
struct PlotMark {
  double t = 0;                // s since the log's first event
  double north = 0, east = 0;  // m
  int waypoint = 0;            // index in the path; for complete, the last waypoint
  bool complete = false;
  bool missed = false;  // not complete: never within kPlotVisitRadius of the waypoint
  double closest = -1;  // m: the closest approach to the waypoint (-1: not known)
};

// `heading_rad` in degrees, plus the multiple of 360 that puts it within 180 of `previous_deg`
// (unwrapping: consecutive headings never jump by more than 180).
double unwrap_deg(double previous_deg, double heading_rad);

struct PlotData {
  std::string trajectory_source;  // channel used for the trajectory
  std::size_t trajectory_rows = 0, path_points = 0, setpoint_rows = 0, progress_rows = 0,
              command_rows = 0, allocation_rows = 0;
  std::vector<std::string> thruster_names;
  std::vector<PlotMark> marks;  // in time order
};

// Writes traj.csv, path.csv, setpoint.csv, progress.csv, cmd.csv, alloc.csv, reached.csv,
// missed.csv and complete.csv (the marks) into `dir`.
PlotData write_plot_data(const std::vector<Event>& log, const std::string& dir);

// A gnuplot script drawing the files in `dir` into `png` (panels without data are left out).
std::string gnuplot_script(const PlotData& d, const std::string& dir, const std::string& png,
                           const std::string& title);

}  // namespace tiller::logtools
