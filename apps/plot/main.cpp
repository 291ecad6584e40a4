// tiller-plot: draws a run from its log into one PNG with gnuplot: path and trajectory from
// above, speed against setpoint, heading, path-following errors, thruster commands, saturation.
//   tiller-plot LOG [--output FILE.png] [--data-dir DIR]
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "logtools/log_io.hpp"
#include "logtools/plotdata.hpp"
#include "runtime/app.hpp"
#include "runtime/log.hpp"

using namespace tiller;

int main(int argc, char** argv) {
  return app::guarded_main("tiller-plot", [&] {
    app::Spec spec{
        "tiller-plot",
        "Draws a run from its LCM log into a PNG with gnuplot: path and trajectory from above "
        "with\n"
        "each waypoint reached, speed, heading (unwrapped), cross-track error and distance to "
        "goal,\n"
        "thruster commands, saturation.",
        "",
        {{"output", "FILE", "PNG to write (default: the log's name with .png)", ""},
         {"data-dir", "DIR",
          "keep the CSV files and the gnuplot script here (default: a temporary directory)", ""}},
        false,   // no config file: --config refused
        false};  // reads a log, opens no LCM: --lcm-url refused
    spec.arguments = "LOG";
    spec.max_positional = 1;
    const app::Args a = app::parse(argc, argv, spec);
    if (a.positional.size() != 1) {
      std::cerr << "tiller-plot: give one log file (see --help)\n";
      return 2;
    }
    namespace fs = std::filesystem;
    const std::string log_path = a.positional[0];
    std::string png = a.get("output");
    if (png.empty()) png = logtools::log_stem(log_path) + ".png";
    png = fs::absolute(png).string();
    const auto log = logtools::read_any_log(log_path);
    if (log.empty()) throw std::runtime_error(log_path + ": the log is empty");
    const bool keep = !a.get("data-dir").empty();
    fs::path dir = keep ? fs::path(a.get("data-dir"))
                        : fs::temp_directory_path() / ("tiller-plot-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    dir = fs::absolute(dir);
    const auto pd = logtools::write_plot_data(log, dir.string());
    const std::string script = (dir / "run.gp").string();
    std::ofstream(script) << logtools::gnuplot_script(pd, dir.string(), png,
                                                      fs::path(log_path).filename().string());
    const pid_t pid = ::fork();
    if (pid == 0) {
      ::execlp("gnuplot", "gnuplot", script.c_str(), static_cast<char*>(nullptr));
      std::cerr << "tiller-plot: cannot run gnuplot (tools/setup installs gnuplot-nox)\n";
      ::_exit(127);
    }
    int st = 0;
    ::waitpid(pid, &st, 0);
    if (!keep) fs::remove_all(dir);
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0 || !fs::exists(png)) {
      std::cerr << "tiller-plot: gnuplot failed" << (keep ? " (script: " + script + ")" : "")
                << "\n";
      return 1;
    }
    std::cout << png << "\n";
    return 0;
  });
}
