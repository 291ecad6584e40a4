#include "logtools/plotdata.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "logtools/lcm_schema.hpp"
#include "runtime/channels.hpp"

namespace tiller::logtools {

namespace {
constexpr double kDeg = 180.0 / 3.14159265358979323846;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}
}  // namespace

PlotData write_plot_data(const std::vector<Event>& log, const std::string& dir) {
  PlotData pd;
  const TypeDb& db = tiller_types();
  const TimeUs t0 = log.empty() ? 0 : log.front().time;
  bool has_truth = false;
  for (const auto& e : log) {
    if (e.channel == channels::kGroundTruth) {
      has_truth = true;
      break;
    }
  }
  pd.trajectory_source = has_truth ? channels::kGroundTruth : channels::kOdometry;
  std::ofstream traj(dir + "/traj.csv"), path(dir + "/path.csv"), sp(dir + "/setpoint.csv"),
      prog(dir + "/progress.csv"), cmd(dir + "/cmd.csv"), alloc(dir + "/alloc.csv");
  traj << "t,north,east,heading_deg,speed\n";
  path << "north,east\n";
  sp << "t,speed,heading_deg,active,heading_valid\n";
  prog << "t,cross_track,distance_to_goal\n";
  cmd << "t,commands...\n";
  alloc << "t,scale,saturated\n";
  std::string last_path;
  Decoded d;
  for (const auto& e : log) {
    const double t = to_seconds(e.time - t0);
    const std::string& ch = e.channel;
    const bool wanted = ch == pd.trajectory_source || ch == channels::kPath ||
                        ch == channels::kVelocitySetpoint || ch == channels::kPathProgress ||
                        ch == channels::kThrusterCommand || ch == channels::kAllocationStatus;
    if (!wanted || !db.decode(e.data.data(), e.data.size(), d)) continue;
    if (ch == pd.trajectory_source) {
      traj << num(t) << "," << num(d.number("position[0]")) << "," << num(d.number("position[1]"))
           << "," << num(d.number("orientation[2]") * kDeg) << ","
           << num(std::hypot(d.number("velocity[0]"), d.number("velocity[1]"))) << "\n";
      ++pd.trajectory_rows;
    } else if (ch == channels::kPath) {
      std::ostringstream os;
      const int n = static_cast<int>(d.number("n_waypoints"));
      for (int k = 0; k < n; ++k) {
        const std::string w = "waypoints[" + std::to_string(k) + "].position";
        os << num(d.number(w + "[0]")) << "," << num(d.number(w + "[1]")) << "\n";
      }
      last_path = os.str();
      pd.path_points = static_cast<std::size_t>(n);
    } else if (ch == channels::kVelocitySetpoint) {
      const bool active = d.number("active") != 0;
      sp << num(t) << ","
         << (active ? num(std::hypot(d.number("velocity[0]"), d.number("velocity[1]"))) : "NaN")
         << ","
         << (active && d.number("heading_valid") != 0 ? num(d.number("target_heading") * kDeg)
                                                      : "NaN")
         << "," << (active ? 1 : 0) << "," << d.number("heading_valid") << "\n";
      ++pd.setpoint_rows;
    } else if (ch == channels::kPathProgress) {
      prog << num(t) << "," << num(d.number("cross_track_error")) << ","
           << num(d.number("distance_to_goal")) << "\n";
      ++pd.progress_rows;
    } else if (ch == channels::kThrusterCommand) {
      const int n = static_cast<int>(d.number("n_thrusters"));
      if (pd.thruster_names.empty()) {
        for (int k = 0; k < n; ++k) {
          const FieldValue* f = d.find("names[" + std::to_string(k) + "]");
          pd.thruster_names.push_back(f ? f->text : "t" + std::to_string(k));
        }
      }
      cmd << num(t);
      for (std::size_t k = 0; k < pd.thruster_names.size(); ++k) {
        cmd << ","
            << (static_cast<int>(k) < n ? num(d.number("command[" + std::to_string(k) + "]"))
                                        : "NaN");
      }
      cmd << "\n";
      ++pd.command_rows;
    } else if (ch == channels::kAllocationStatus) {
      const int n = static_cast<int>(d.number("n_thrusters"));
      int sat = 0;
      for (int k = 0; k < n; ++k)
        sat += d.number("saturated[" + std::to_string(k) + "]") != 0 ? 1 : 0;
      alloc << num(t) << "," << num(d.number("scale")) << "," << sat << "\n";
      ++pd.allocation_rows;
    }
  }
  path << last_path;
  return pd;
}

std::string gnuplot_script(const PlotData& d, const std::string& dir, const std::string& png,
                           const std::string& title) {
  std::ostringstream g;
  auto f = [&](const char* name) { return "'" + dir + "/" + name + "'"; };
  g << "set terminal pngcairo size 1600,1200 font 'sans,10' noenhanced\n"
    << "set output '" << png << "'\n"
    << "set datafile separator ','\nset key top right font 'sans,8'\nset grid\n"
    << "set multiplot layout 3,2 title '" << title << "'\n";
  // 1. Path from above: east to the right, north up, equal scales.
  g << "set title 'path and trajectory from above (" << d.trajectory_source
    << ")'\nset xlabel 'east [m]'\nset ylabel 'north [m]'\n"
    << "set size ratio -1\n";
  std::string plot = "plot ";
  if (d.trajectory_rows)
    plot += f("traj.csv") + " every ::1 using 3:2 with lines lw 2 title 'trajectory', " +
            f("traj.csv") + " every ::1::1 using 3:2 with points pt 7 ps 1.5 title 'start', ";
  if (d.path_points)
    plot += f("path.csv") +
            " every ::1 using 2:1 with linespoints pt 6 ps 1.5 dt 2 title 'path (waypoints)', ";
  if (plot == "plot ") plot = "plot 0 notitle, ";
  g << plot.substr(0, plot.size() - 2) << "\nset size noratio\nset xlabel 'time [s]'\n";
  // 2. Speed against setpoint.
  g << "set title 'speed over ground vs setpoint'\nset ylabel 'speed [m/s]'\n";
  plot = "plot ";
  if (d.trajectory_rows) plot += f("traj.csv") + " every ::1 using 1:5 with lines title 'speed', ";
  if (d.setpoint_rows)
    plot += f("setpoint.csv") + " every ::1 using 1:2 with lines dt 2 lw 2 title 'setpoint', ";
  if (plot == "plot ") plot = "plot 0 notitle, ";
  g << plot.substr(0, plot.size() - 2) << "\n";
  // 3. Heading.
  g << "set title 'heading'\nset ylabel 'heading [deg]'\nset yrange [-180:180]\nset ytics 90\n";
  plot = "plot ";
  if (d.trajectory_rows)
    plot += f("traj.csv") + " every ::1 using 1:4 with points pt 7 ps 0.3 title 'heading', ";
  if (d.setpoint_rows)
    plot +=
        f("setpoint.csv") + " every ::1 using 1:3 with points pt 7 ps 0.2 title 'target heading', ";
  if (plot == "plot ") plot = "plot 0 notitle, ";
  g << plot.substr(0, plot.size() - 2) << "\nset autoscale y\nset ytics autofreq\n";
  // 4. Path-following errors.
  g << "set title 'path following'\nset ylabel 'm'\n";
  if (d.progress_rows) {
    g << "plot " << f("progress.csv")
      << " every ::1 using 1:2 with lines title 'cross-track error', " << f("progress.csv")
      << " every ::1 using 1:3 with lines title 'distance to goal'\n";
  } else {
    g << "plot 0 title 'no TILLER_PATH_PROGRESS'\n";
  }
  // 5. Thruster commands.
  g << "set title 'thruster commands'\nset ylabel 'command [-1, 1]'\nset yrange [-1.1:1.1]\n";
  if (d.command_rows && !d.thruster_names.empty()) {
    g << "plot ";
    for (std::size_t k = 0; k < d.thruster_names.size(); ++k) {
      g << (k ? ", " : "") << f("cmd.csv") << " every ::1 using 1:" << k + 2
        << " with lines title '" << d.thruster_names[k] << "'";
    }
    g << "\n";
  } else {
    g << "plot 0 title 'no TILLER_THRUSTER_COMMAND'\n";
  }
  g << "set autoscale y\n";
  // 6. Saturation.
  g << "set title 'allocation: scale kept and thrusters saturated'\nset ylabel 'scale'\nset "
       "y2label 'saturated thrusters'\n"
    << "set yrange [0:1.05]\nset y2range [0:" << std::max<std::size_t>(1, d.thruster_names.size())
    << ".5]\nset y2tics 1\n";
  if (d.allocation_rows) {
    g << "plot " << f("alloc.csv")
      << " every ::1 using 1:2 with lines title 'scale (1 = demand met)', " << f("alloc.csv")
      << " every ::1 using 1:3 axes x1y2 with steps title 'saturated'\n";
  } else {
    g << "plot 0 title 'no TILLER_ALLOCATION_STATUS'\n";
  }
  g << "unset multiplot\n";
  return g.str();
}

}  // namespace tiller::logtools
