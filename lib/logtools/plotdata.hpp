// The data of a run plot, extracted from a log: trajectory seen from above (ground truth when
// the simulator logged it, else odometry), the path's waypoints, speed over ground against the
// velocity setpoint, heading against the target heading, cross-track error, thruster commands
// and saturation. Written as CSV files plus a gnuplot script that draws them into one PNG
// (tiller-plot). Times in s since the log's first event; headings in degrees for people.
#pragma once

#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

struct PlotData {
  std::string trajectory_source;  // channel used for the trajectory
  std::size_t trajectory_rows = 0, path_points = 0, setpoint_rows = 0, progress_rows = 0,
              command_rows = 0, allocation_rows = 0;
  std::vector<std::string> thruster_names;
};

// Writes traj.csv, path.csv, setpoint.csv, progress.csv, cmd.csv, alloc.csv into `dir`.
PlotData write_plot_data(const std::vector<Event>& log, const std::string& dir);

// A gnuplot script drawing the files in `dir` into `png` (panels without data are left out).
std::string gnuplot_script(const PlotData& d, const std::string& dir, const std::string& png,
                           const std::string& title);

}  // namespace tiller::logtools
