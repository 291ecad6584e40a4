// tiller-run --sweep: many runs of one mission (lib/runtool/run.hpp), one per point of a list or
// a grid of one or two axes, run in parallel as separate processes (each run is independent and
// deterministic: the same point gives the same numbers whatever the order or the job count),
// printed as a table and drawn as a PNG with gnuplot.
//
// An axis is NAME=FROM:TO:COUNT (COUNT evenly spaced numbers, both ends included) or
// NAME=V1,V2,... (commas inside [...] or {...} do not split). NAME is
//   FILE.KEY            a setting of one config file (FILE: sim, esc, mixer, control, guidance;
//                       KEY: the dotted key path inside it, e.g. control.velocity_pid.yaw.k_error)
//   vehicle, sim, esc, mixer, control, guidance
//                       the config file itself (values are files, or short names: see
//                       expand_file), e.g. guidance=otter,seed
//   current-speed, current-toward-deg, seed, north, east, heading-deg
//                       the simulator's option of that name (tiller-sim --NAME)
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "runtool/run.hpp"

namespace tiller::runtool {

struct Axis {
  std::string name;
  std::vector<std::string> values;  // as text
  bool numeric = false;             // every value a number (plotted against its value)
};

// Parses an axis; throws std::runtime_error naming what is wrong.
Axis parse_axis(const std::string& text);

// "a,[1,2],b" -> {"a", "[1,2]", "b"}: commas inside brackets, braces or quotes do not split.
std::vector<std::string> split_top_level(const std::string& s);

// A config file given by a short name: "otter" for kind guidance is config/guidance/otter.yaml
// (vehicle: config/vehicles/, esc: config/esc/); a value with a '/' or a .yaml/.yml/.csv ending
// is a path and is returned as it is.
std::string expand_file(const std::string& kind, const std::string& value);

// The spec of one point: `base` with the axes' values at `index` applied.
RunSpec spec_at(const RunSpec& base, const std::vector<Axis>& axes,
                const std::vector<std::size_t>& index);

// The numbers of one run, as the table and the plot show them.
struct Row {
  std::vector<std::size_t> index;  // into each axis' values
  bool ok = false;
  std::string error;  // when !ok
  bool completed = false;
  double xte_rms = 0, xte_max = 0, time_s = -1, final_m = 0, heading_rad = -1, vrx_way = 0,
         vrx_sk = -1, sim_s = 0;
  int missed = 0;
  // lib/scores/path_metrics.hpp up to the path's completion (RunScores::corners, as tiller-score
  // prints it): steady cross-track RMS (from 60 s after each waypoint passage to 10 m before the
  // next; -1: no leg that long), largest corner overshoot (m), weaving (RMS heading rate on the
  // steady stretches, rad/s; -1: none); and the largest speed setpoint (m/s) with the
  // follower's max_speed.
  double steady_rms = -1, overshoot = 0, weaving = -1, max_setpoint = 0, max_speed = 0;
  double path_m = 0;     // m: the length of the path as followed (for time / (length / cruise))
  double final_30 = -1;  // m: distance to the goal 30 s after completion (or at the end); -1: none
  double est_rms = -1, est_head_deg = -1;  // estimation error RMS (m, deg); -1: on the truth
  // On estimated state, the path scored on the estimate (the pose the follower followed): the
  // cross-track RMS to the completion, the steady cross-track RMS as steady_rms (m; -1: on the
  // truth, or no leg that long), waypoints missed by the estimate.
  double est_xte_rms = -1, est_steady_rms = -1;
  int est_missed = 0;
};

// The row of a finished run.
Row row_of(const RunOutcome& o);

// Runs every point of the grid (the first axis varies slowest), at most `jobs` at a time, each
// in its own process; `log_dir` non-empty: each run's log there (run-<i>.lcmlog). The rows come
// back in grid order. A run that fails (a config error, a crash) is a row with !ok.
std::vector<Row> sweep(const RunSpec& base, const std::vector<Axis>& axes, int jobs,
                       const std::string& log_dir = "");

// The table: one line per run, the axis values then the scores; then the best run per score.
void print_table(const std::vector<Axis>& axes, const std::vector<Row>& rows, std::FILE* out);
// The same as CSV (a header line, then one line per run).
std::string csv(const std::vector<Axis>& axes, const std::vector<Row>& rows);

// A gnuplot script drawing the rows into `png`: one axis, each score against the axis' value
// (or its index, labelled with the values); two axes, a heat map of each score over the grid
// with each cell's value written in it. `data_file` is the CSV written by csv().
std::string gnuplot_script(const std::vector<Axis>& axes, const std::vector<Row>& rows,
                           const std::string& data_file, const std::string& png,
                           const std::string& title);

// Runs gnuplot on a script file; true when it exited 0.
bool run_gnuplot(const std::string& script);

}  // namespace tiller::runtool
