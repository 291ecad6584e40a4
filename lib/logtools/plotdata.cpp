#include "logtools/plotdata.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/angles.hpp"
#include "logtools/lcm_schema.hpp"
#include "runtime/channels.hpp"

namespace tiller::logtools {

namespace {
std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}
}  // namespace

double unwrap_deg(double previous_deg, double heading_rad) {
  return previous_deg + rad_to_deg(angle_diff(heading_rad, deg_to_rad(previous_deg)));
}

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
      prog(dir + "/progress.csv"), cmd(dir + "/cmd.csv"), alloc(dir + "/alloc.csv"),
      reached(dir + "/reached.csv"), missed(dir + "/missed.csv"), complete(dir + "/complete.csv");
  traj << "t,north,east,heading_deg,speed\n";
  path << "north,east\n";
  sp << "t,speed,heading_deg,active,heading_valid\n";
  prog << "t,cross_track,distance_to_goal\n";
  cmd << "t,commands...\n";
  alloc << "t,scale,saturated\n";
  reached << "t,north,east,waypoint\n";
  missed << "t,north,east,waypoint,closest\n";
  complete << "t,north,east,waypoint\n";
  std::string last_path;
  Decoded d;
  // Unwrapped headings: the vehicle's continues from its previous one; the target's is put
  // nearest the vehicle's (so the two are compared without a 360 offset).
  std::optional<double> heading_deg;
  double north = 0, east = 0;  // the latest trajectory point
  std::int64_t progress_path = -1;
  int segment = -1;
  bool was_complete = false;
  struct Point {
    double t, north, east;
  };
  std::vector<Point> track;                   // the trajectory, for the closest approaches
  std::vector<std::pair<double, double>> wp;  // the latest path's waypoints
  auto mark = [&](double t, int waypoint, bool done) {
    pd.marks.push_back({t, north, east, waypoint, done});
  };
  for (const auto& e : log) {
    const double t = to_seconds(e.time - t0);
    const std::string& ch = e.channel;
    const bool wanted = ch == pd.trajectory_source || ch == channels::kPath ||
                        ch == channels::kVelocitySetpoint || ch == channels::kPathProgress ||
                        ch == channels::kThrusterCommand || ch == channels::kAllocationStatus;
    if (!wanted || !db.decode(e.data.data(), e.data.size(), d)) continue;
    if (ch == pd.trajectory_source) {
      const double yaw = d.number("orientation[2]");
      heading_deg = heading_deg ? unwrap_deg(*heading_deg, yaw) : rad_to_deg(wrap_pi(yaw));
      north = d.number("position[0]");
      east = d.number("position[1]");
      track.push_back({t, north, east});
      traj << num(t) << "," << num(north) << "," << num(east) << "," << num(*heading_deg) << ","
           << num(std::hypot(d.number("velocity[0]"), d.number("velocity[1]"))) << "\n";
      ++pd.trajectory_rows;
    } else if (ch == channels::kPath) {
      std::ostringstream os;
      const int n = static_cast<int>(d.number("n_waypoints"));
      wp.clear();
      for (int k = 0; k < n; ++k) {
        const std::string w = "waypoints[" + std::to_string(k) + "].position";
        wp.emplace_back(d.number(w + "[0]"), d.number(w + "[1]"));
        os << num(d.number(w + "[0]")) << "," << num(d.number(w + "[1]")) << "\n";
      }
      last_path = os.str();
      pd.path_points = static_cast<std::size_t>(n);
    } else if (ch == channels::kVelocitySetpoint) {
      const bool active = d.number("active") != 0;
      sp << num(t) << ","
         << (active ? num(std::hypot(d.number("velocity[0]"), d.number("velocity[1]"))) : "NaN")
         << ","
         << (active && d.number("heading_valid") != 0
                 ? num(unwrap_deg(heading_deg.value_or(0.0), d.number("target_heading")))
                 : "NaN")
         << "," << (active ? 1 : 0) << "," << d.number("heading_valid") << "\n";
      ++pd.setpoint_rows;
    } else if (ch == channels::kPathProgress) {
      prog << num(t) << "," << num(d.number("cross_track_error")) << ","
           << num(d.number("distance_to_goal")) << "\n";
      ++pd.progress_rows;
      // A new path starts the marks again; moving from segment s to s' reached waypoints
      // s+1..s'; complete becoming true is the mission's end (at the last waypoint).
      const auto path_id = static_cast<std::int64_t>(d.number("path_id"));
      const int seg = static_cast<int>(d.number("segment"));
      const bool done = d.number("complete") != 0;
      if (path_id != progress_path) {
        progress_path = path_id;
        segment = seg;
        was_complete = false;
      }
      for (int k = std::max(segment, 0) + 1; k <= seg; ++k) mark(t, k, false);
      segment = std::max(segment, seg);
      if (done && !was_complete) mark(t, static_cast<int>(d.number("n_waypoints")) - 1, true);
      was_complete = done;
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
  // Reached or missed: the closest approach to the waypoint from the previous mark to the next
  // one (a turn anticipated switches before the point and passes it after the switch).
  for (std::size_t i = 0; i < pd.marks.size(); ++i) {
    PlotMark& m = pd.marks[i];
    const double from = i > 0 ? pd.marks[i - 1].t : -1e300;
    const double to = i + 1 < pd.marks.size() ? pd.marks[i + 1].t : 1e300;
    if (!m.complete && m.waypoint >= 0 && static_cast<std::size_t>(m.waypoint) < wp.size()) {
      double best = 1e300;
      for (const Point& p : track) {
        if (p.t < from || p.t > to) continue;
        best = std::min(best, std::hypot(p.north - wp[static_cast<std::size_t>(m.waypoint)].first,
                                         p.east - wp[static_cast<std::size_t>(m.waypoint)].second));
      }
      if (best < 1e300) {
        m.closest = best;
        m.missed = best >= kPlotVisitRadius;
      }
    }
    if (m.complete)
      complete << num(m.t) << "," << num(m.north) << "," << num(m.east) << "," << m.waypoint
               << "\n";
    else if (m.missed)
      missed << num(m.t) << "," << num(m.north) << "," << num(m.east) << "," << m.waypoint << ","
             << num(m.closest) << "\n";
    else
      reached << num(m.t) << "," << num(m.north) << "," << num(m.east) << "," << m.waypoint << "\n";
  }
  return pd;
}

std::string gnuplot_script(const PlotData& d, const std::string& dir, const std::string& png,
                           const std::string& title) {
  std::ostringstream g;
  auto f = [&](const char* name) { return "'" + dir + "/" + name + "'"; };
  // Ends a plot command built as "plot a, b, " (a placeholder when no panel data).
  auto finish = [](std::string plot) {
    if (plot == "plot ") plot = "plot 0 notitle, ";
    return plot.substr(0, plot.size() - 2) + "\n";
  };
  std::size_t n_reached = 0, n_missed = 0, n_complete = 0;
  for (const auto& m : d.marks) ++(m.complete ? n_complete : (m.missed ? n_missed : n_reached));
  g << "set terminal pngcairo size 1600,1200 font 'sans,10' noenhanced\n"
    << "set output '" << png << "'\n"
    << "set datafile separator ','\nset key top right font 'sans,8'\nset grid\n"
    << "set multiplot layout 3,2 title '" << title << "'\n";
  // 1. Path from above: east to the right, north up, equal scales; the legend below the track.
  g << "set title 'path and trajectory from above (" << d.trajectory_source
    << ")'\nset xlabel 'east [m]'\nset ylabel 'north [m]'\n"
    << "set size ratio -1\nset key outside below horizontal\n";
  std::string plot = "plot ";
  if (d.trajectory_rows)
    plot += f("traj.csv") + " every ::1 using 3:2 with lines lw 2 title 'trajectory', " +
            f("traj.csv") + " every ::1::1 using 3:2 with points pt 7 ps 1.5 title 'start', ";
  if (d.path_points)
    plot += f("path.csv") +
            " every ::1 using 2:1 with linespoints pt 6 ps 1.5 dt 2 title 'path (waypoints)', ";
  if (n_reached)
    plot += f("reached.csv") +
            " every ::1 using 3:2:(sprintf('%d', $4)) with labels point pt 5 ps 1.2 offset 1,1 "
            "title 'waypoint reached (index)', ";
  if (n_missed)
    plot += f("missed.csv") +
            " every ::1 using 3:2:(sprintf('%d missed, %.2f m', $4, $5)) with labels point pt 2 "
            "ps 2 lc rgb 'red' tc rgb 'red' offset 1,-1 title 'waypoint MISSED (index, closest "
            "approach)', ";
  if (n_complete)
    plot += f("complete.csv") +
            " every ::1 using 3:2 with points pt 9 ps 2.5 lc rgb 'dark-green' title 'mission "
            "complete', ";
  g << finish(plot) << "set size noratio\nset key inside top right\nset xlabel 'time [s]'\n";
  // The marks on every time panel: a dotted line at each waypoint reached, a solid one at the
  // mission's completion.
  int tag = 1;
  for (const auto& m : d.marks) {
    g << "set arrow " << tag << " from first " << num(m.t) << ", graph 0 to first " << num(m.t)
      << ", graph 1 nohead " << (m.complete ? "lw 2 lc rgb 'dark-green'" : "dt 3 lc rgb 'gray40'")
      << " back\n"
      << "set label " << tag << " '"
      << (m.complete ? "complete" : std::to_string(m.waypoint) + (m.missed ? " missed" : ""))
      << "' at first " << num(m.t) << ", graph 0.03 offset 0.3,0 font 'sans,7'\n";
    ++tag;
  }
  // 2. Speed against setpoint.
  g << "set title 'speed over ground vs setpoint'\nset ylabel 'speed [m/s]'\n";
  plot = "plot ";
  if (d.trajectory_rows) plot += f("traj.csv") + " every ::1 using 1:5 with lines title 'speed', ";
  if (d.setpoint_rows)
    plot += f("setpoint.csv") + " every ::1 using 1:2 with lines dt 2 lw 2 title 'setpoint', ";
  g << finish(plot);
  // 3. Heading, unwrapped (no jumps at +-180).
  g << "set title 'heading (unwrapped)'\nset ylabel 'heading [deg]'\nset ytics 90\n";
  plot = "plot ";
  if (d.trajectory_rows)
    plot += f("traj.csv") + " every ::1 using 1:4 with lines lw 2 title 'heading', ";
  if (d.setpoint_rows)
    plot += f("setpoint.csv") + " every ::1 using 1:3 with lines dt 2 title 'target heading', ";
  g << finish(plot) << "set ytics autofreq\n";
  // 4. Path-following errors: cross-track (about a metre) on the left axis, distance to goal
  // (up to the path's length) on the right one.
  g << "set title 'path following'\nset ylabel 'cross-track error [m] (+ = right of path)'\n";
  if (d.progress_rows) {
    g << "set y2label 'distance to goal [m]'\nset ytics nomirror\nset y2tics\n"
      << "plot " << f("progress.csv")
      << " every ::1 using 1:2 with lines lw 2 title 'cross-track error (left axis)', "
      << f("progress.csv")
      << " every ::1 using 1:3 axes x1y2 with lines title 'distance to goal (right axis)'\n"
      << "unset y2tics\nunset y2label\nset ytics mirror\n";
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
    << ".5]\nset ytics nomirror\nset y2tics 1\n";
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
