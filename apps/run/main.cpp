// tiller-run: flies a mission file on the simulated vehicle in lockstep (simulated time, as fast
// as the CPU goes) with the real node classes and config files of a live simulated run, then
// prints tiller-score's scores; --log FILE writes the run's LCM log. With --sweep (and --sweep2)
// it runs the mission once per point of a list or a grid, in parallel, and prints a table and
// draws a PNG. The logic: lib/runtool (run.hpp, sweep.hpp); the guide: docs/tuning.md.
//   tiller-run config/missions/default.yaml --current-speed 0.3 --current-toward-deg 210
//   tiller-run config/missions/default.yaml --sweep control.velocity_pid.yaw.k_error=20:80:4
//   tiller-run config/missions/harbour.plan      (a QGroundControl plan: docs/missions.md)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <utility>

#include "core/angles.hpp"
#include "mission/start_gate_options.hpp"
#include "runtime/app.hpp"
#include "runtool/run.hpp"
#include "runtool/sweep.hpp"
#include "sim/sim_options.hpp"

using namespace tiller;

namespace {
const char* kSimFlags[] = {"odometry",    "sensors",       "gnss-outage",
                           "seed",        "north",         "east",
                           "heading-deg", "current-speed", "current-toward-deg",
                           "mass-scale",  "damping-scale", "dvl-outage",
                           "force-step"};

app::Spec spec() {
  app::Spec s{
      "tiller-run",
      "Flies a mission on the simulated vehicle in lockstep with the real nodes and "
      "configs,\nprints tiller-score's scores; --sweep: many runs in parallel, a table "
      "and a PNG.",
      "",
      {{"vehicle", "FILE", "vehicle file, or a name in config/vehicles/",
        "config/vehicles/otter.yaml"},
       {"sim", "FILE", "simulator config (current, wind, noise: docs/tuning.md)",
        "config/sim/sim.yaml"},
       {"esc", "FILE", "ESC config, backend sim (default: config/esc/VEHICLE_sim.yaml)", ""},
       {"mixer", "FILE", "mixer config (default: config/mixer/VEHICLE.yaml)", ""},
       {"control", "FILE", "controller config (default: config/control/VEHICLE.yaml)", ""},
       {"guidance", "FILE", "path follower config (default: config/guidance/VEHICLE.yaml)", ""},
       {"set", "LIST",
        "config settings FILE.KEY=VALUE[,...] (FILE: sim, esc, mixer, control, guidance, nav)", ""},
       {"hold-s", "S", "station keeping after completion, s >= 0 (default: the mission's)", ""},
       {"time-limit-s", "S", "simulated time limit, s > 0 (default: the mission's)", ""},
       {"settle-s", "S", "the simulator (and tiller-nav) alone for S s before the mission", ""},
       {"log", "FILE", "write the run's LCM log here (and FILE's .replay.yaml)", ""},
       {"sweep", "AXIS", "NAME=FROM:TO:COUNT or NAME=V1,V2,... (see docs/tuning.md)", ""},
       {"sweep2", "AXIS", "a second axis: every combination of the two", ""},
       {"jobs", "N", "sweep: runs at a time, 1..256 (default: the number of cores)", ""},
       {"plot", "PNG", "sweep: the PNG (and FILE's .csv beside it)", "sweep.png"},
       {"log-dir", "DIR", "sweep: keep each run's log here (run-I.lcmlog)", ""}},
      false,   // several config files, each by its own option: --config refused
      false};  // lockstep, opens no LCM: --lcm-url refused
  const auto sim = sim_options();
  for (const char* f : kSimFlags) {
    for (const auto& o : sim)
      if (o.name == f) s.options.push_back(o);
  }
  for (auto& o : mission::start_gate_options()) s.options.push_back(std::move(o));
  s.arguments = "MISSION_FILE";
  s.max_positional = 1;
  return s;
}

runtool::RunSpec run_spec(const app::Args& a) {
  if (a.positional.size() != 1)
    throw std::runtime_error("give one mission file (tiller-run --help)");
  runtool::RunSpec s;
  s.mission_file = a.positional[0];
  s.vehicle_file = runtool::expand_file("vehicle", a.get("vehicle"));
  s.sim_file = runtool::expand_file("sim", a.get("sim"));
  using S = runtool::RunSpec;
  const std::pair<const char*, std::string S::*> files[] = {{"esc", &S::esc_file},
                                                            {"mixer", &S::mixer_file},
                                                            {"control", &S::control_file},
                                                            {"guidance", &S::guidance_file}};
  for (const auto& [k, member] : files) {
    if (!a.get(k).empty()) s.*member = runtool::expand_file(k, a.get(k));
  }
  for (const char* f : kSimFlags) {
    if (!a.get(f).empty()) s.sim_args.insert(s.sim_args.end(), {std::string("--") + f, a.get(f)});
  }
  sim_overrides(s.sim_args);  // checks the numbers now: exit 2 before anything runs
  for (const auto& t : runtool::split_top_level(a.get("set"))) {
    try {
      s.settings.push_back(runtool::parse_setting(t));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("--set: ") + e.what());
    }
  }
  if (!a.get("hold-s").empty())
    s.hold_s = app::number_option(a, "hold-s", 0, 1e6, "a number of seconds in [0, 1e6]");
  if (!a.get("time-limit-s").empty())
    s.time_limit_s =
        app::number_option(a, "time-limit-s", 1e-3, 1e6, "a number of seconds in [0.001, 1e6]");
  if (!a.get("settle-s").empty())
    s.settle_s = app::number_option(a, "settle-s", 0, 1e6, "a number of seconds in [0, 1e6]");
  s.start_gate = mission::start_gate_params(a);
  s.log_file = a.get("log");
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int single(const runtool::RunSpec& s) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto o = runtool::run(s);
  const double wall = seconds_since(t0);
  const auto& f = o.files;
  std::printf("tiller-run: %s on %s, starting at north %.2f m, east %.2f m, heading %.1f deg\n",
              f.mission.c_str(), f.vehicle.c_str(), o.start_north, o.start_east,
              rad_to_deg(o.start_heading));
  std::printf("tiller-run: configs sim %s, esc %s, mixer %s, control %s, guidance %s\n",
              f.sim.c_str(), f.esc.c_str(), f.mixer.c_str(), f.control.c_str(), f.guidance.c_str());
  for (const auto& st : s.settings) std::printf("tiller-run: set %s\n", st.text().c_str());
  std::printf("tiller-run: %s; %.1f s simulated in %.3f s wall (%.0fx real time), %zu messages\n",
              o.completed ? "mission complete" : "mission NOT complete", o.sim_s, wall,
              o.sim_s / std::max(wall, 1e-9), o.messages);
  if (s.start_gate.enabled)
    std::printf("tiller-run: start gate (position 1-sigma <= %.2f m for %.1f s): %s %.1f s\n",
                s.start_gate.max_position_std_m, s.start_gate.settle_s,
                o.started_at >= 0 ? "the mission started at" : "never opened in",
                o.started_at >= 0 ? o.started_at : o.sim_s);
  std::printf("\n");
  scores::print_scores(o.scores, stdout);
  if (o.rov && o.depth_from_s >= 0) {
    std::printf(
        "depth error         RMS %.3f m (max %.3f m) against the path's depth, from %.1f s "
        "(first within 0.1 m)\n",
        o.depth_rms_m, o.depth_max_m, o.depth_from_s);
  } else if (o.rov) {
    std::printf("depth error         - (never within 0.1 m of the path's depth)\n");
  }
  if (o.estimated) {
    std::printf(
        "odometry            dead reckoning %.1f s, invalid %.1f s (after the first valid); "
        "%zu disarm requests; largest position step %.2f m; largest thruster command step "
        "%.3f in the 10 s after dead reckoning\n",
        o.dead_reckoning_s, o.odometry_invalid_s, o.disarm_requests, o.max_position_step_m,
        o.recovery_command_step);
  }
  if (!s.log_file.empty()) {
    const std::string m = runtool::replay_manifest(s, f);
    const std::filesystem::path p(s.log_file);
    const std::string manifest = (p.parent_path() / p.stem()).string() + ".replay.yaml";
    if (!m.empty()) std::ofstream(manifest) << m;
    std::printf("\ntiller-run: log %s (tiller-log summary, tiller-plot, tiller-replay read it)\n",
                s.log_file.c_str());
    if (m.empty())
      std::printf(
          "tiller-run: no replay manifest: --set changed a config in memory, or --settle-s "
          "took part\n");
  }
  return o.completed ? 0 : 1;
}

int sweep(const app::Args& a, const runtool::RunSpec& s) {
  std::vector<runtool::Axis> axes;
  for (const char* k : {"sweep", "sweep2"}) {
    if (a.get(k).empty()) continue;
    try {
      axes.push_back(runtool::parse_axis(a.get(k)));
    } catch (const std::exception& e) {
      throw std::runtime_error("--" + std::string(k) + ": " + e.what());
    }
  }
  if (axes.empty()) throw std::runtime_error("--sweep2: expected together with --sweep");
  if (!s.log_file.empty())
    throw std::runtime_error("--log: one run's log; a sweep takes --log-dir DIR");
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const int jobs =
      a.get("jobs").empty()
          ? static_cast<int>(cores)
          : static_cast<int>(app::integer_option(a, "jobs", 1, 256, "a whole number in [1, 256]"));
  const std::size_t n =
      axes.size() == 1 ? axes[0].values.size() : axes[0].values.size() * axes[1].values.size();
  const auto files = runtool::resolve_files(s);  // a missing file: exit 2 before any run
  bool vehicle_axis = false;
  for (const auto& x : axes) vehicle_axis |= x.name == "vehicle";
  const std::string vehicle = vehicle_axis ? "each vehicle of the axis"
                                           : std::filesystem::path(files.vehicle).stem().string();
  std::printf("tiller-run: sweep, %zu runs of %s on %s, %d at a time\n", n, files.mission.c_str(),
              vehicle.c_str(), jobs);
  const auto t0 = std::chrono::steady_clock::now();
  const auto rows = runtool::sweep(s, axes, jobs, a.get("log-dir"));
  const double wall = seconds_since(t0);
  double sim = 0;
  std::size_t failed = 0;
  for (const auto& r : rows) {
    sim += r.sim_s;
    failed += r.ok ? 0 : 1;
  }
  runtool::print_table(axes, rows, stdout);
  std::printf("tiller-run: %zu runs, %.0f s simulated in %.2f s wall (%.0fx real time)\n", n, sim,
              wall, sim / std::max(wall, 1e-9));
  if (failed == rows.size()) {
    std::fprintf(stderr, "tiller-run: every run failed: %s\n", rows.front().error.c_str());
    return 2;
  }
  namespace fs = std::filesystem;
  const std::string png = fs::absolute(a.get("plot")).string();
  const std::string stem = (fs::path(png).parent_path() / fs::path(png).stem()).string();
  std::ofstream(stem + ".csv") << runtool::csv(axes, rows);
  std::ofstream(stem + ".gp") << runtool::gnuplot_script(
      axes, rows, stem + ".csv", png,
      fs::path(files.mission).filename().string() + " on " + vehicle);
  if (!runtool::run_gnuplot(stem + ".gp") || !fs::exists(png)) {
    std::fprintf(stderr, "tiller-run: gnuplot failed (script %s.gp)\n", stem.c_str());
    return 1;
  }
  fs::remove(stem + ".gp");
  std::printf("tiller-run: table %s.csv, plot %s\n", stem.c_str(), png.c_str());
  return failed ? 1 : 0;
}
}  // namespace

int main(int argc, char** argv) {
  const app::Args a = app::parse(argc, argv, spec());
  return app::guarded_main("tiller-run", [&] {
    const runtool::RunSpec s = run_spec(a);
    const bool sweeping = !a.get("sweep").empty() || !a.get("sweep2").empty();
    if (!sweeping) {
      for (const char* k : {"jobs", "log-dir"})
        if (!a.get(k).empty())
          throw std::runtime_error("--" + std::string(k) + ": expected together with --sweep");
    }
    return sweeping ? sweep(a, s) : single(s);
  });
}
