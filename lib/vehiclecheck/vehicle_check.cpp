#include "vehiclecheck/vehicle_check.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "control/control_config.hpp"
#include "control/rov_config.hpp"
#include "core/config.hpp"
#include "esc/esc_config.hpp"
#include "guidance/follower_config.hpp"
#include "launch/launch_file.hpp"
#include "mixer/mixer_node.hpp"
#include "sim/sim_node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller::vehiclecheck {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> yaml_files(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".yaml") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The text names `file_name` as a path's last component (after '/', a space, '[', ',', a quote
// or '=', or at the start), e.g. "config/vehicles/otter.yaml" but not "my_otter.yaml".
bool names_file(const std::string& text, const std::string& file_name) {
  std::size_t at = 0;
  while ((at = text.find(file_name, at)) != std::string::npos) {
    const char before = at == 0 ? ' ' : text[at - 1];
    const std::size_t end = at + file_name.size();
    const char after = end < text.size() ? text[end] : ' ';
    const bool starts = std::string(" /[,'\"=:-\t\n").find(before) != std::string::npos;
    const bool ends = std::isalnum(static_cast<unsigned char>(after)) == 0 && after != '_';
    if (starts && ends) return true;
    at = end;
  }
  return false;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return fs::equivalent(a, b, ec) && !ec;
}

class Checker {
 public:
  Checker(std::string vehicle, std::string root)
      : vehicle_(std::move(vehicle)), root_(std::move(root)) {}

  Report run() {
    const std::string name = fs::path(vehicle_).stem().string();
    const std::string file_name = fs::path(vehicle_).filename().string();
    // 1-2. The vehicle file, read as the simulator reads it (thrusters and dynamics, every key).
    bool surface = false;
    if (!attempt(vehicle_, [&] {
          const auto v = load_sim_vehicle_file(vehicle_);
          surface = v.dynamics.kind == sim::ModelKind::kSurface3Dof;
          return std::to_string(v.vehicle.thrusters.size()) + " thrusters, " +
                 (surface ? "surface_3dof" : "underwater_6dof") +
                 " dynamics (tiller-sim, tiller-mixer)";
        })) {
      return std::move(report_);
    }
    // 3. Mixer configs naming this vehicle.
    std::vector<std::string> mine;  // this vehicle's mixer and ESC configs, for the launch files
    int mixers = 0;
    for (const auto& p : yaml_files(fs::path(root_) / "mixer")) {
      if (!names_vehicle(p)) continue;
      ++mixers;
      mine.push_back(p.filename().string());
      attempt(p.string(), [&] {
        const MixerNode node(p.string());
        if (!same_file(node.params().vehicle_file, vehicle_))
          throw config::Error("vehicle: names " + node.params().vehicle_file + ", not " + vehicle_);
        const std::string d = node.allocator().describe();
        return "tiller-mixer: " + d.substr(0, d.find('\n'));
      });
    }
    if (mixers == 0)
      missing(fs::path(root_) / "mixer" / (name + ".yaml"), "no mixer config names " + file_name);
    // 4-5. ESC configs naming this vehicle (the loader checks one ESC per thruster name).
    int escs = 0;
    for (const auto& p : yaml_files(fs::path(root_) / "esc")) {
      if (!names_vehicle(p)) continue;
      ++escs;
      mine.push_back(p.filename().string());
      attempt(p.string(), [&] {
        const auto c = esc::load_esc_config_file(p.string());
        if (!same_file(c.vehicle_file, vehicle_))
          throw config::Error("vehicle: names " + c.vehicle_file + ", not " + vehicle_);
        return "tiller-esc: backend " + c.backend + ", " + std::to_string(c.escs.size()) +
               " ESCs, one per thruster";
      });
    }
    if (escs == 0)
      missing(fs::path(root_) / "esc" / (name + "_sim.yaml"), "no ESC config names " + file_name);
    // 6. Controllers of the same name.
    const fs::path control = fs::path(root_) / "control" / (name + ".yaml");
    if (fs::exists(control)) {
      attempt(control.string(), [&] {
        const auto root = config::Value::load_file(control.string());
        if (root.has("rov_control")) {  // an ROV's pilot modes (tiller-rov-control)
          const auto p = control::load_rov_control_file(control.string());
          if (!same_file(p.vehicle_file, vehicle_))
            throw config::Error("rov_control.vehicle: names " + p.vehicle_file + ", not " +
                                vehicle_);
          return std::string("tiller-rov-control");
        }
        control::load_velocity_pid_node_params(root);
        control::load_station_keep_node_params(config::Value::load_file(control.string()));
        return std::string("tiller-velocity-pid, tiller-station-keep");
      });
    } else {
      note(control, surface ? "absent: needed for closed-loop manual and autonomy on this boat"
                            : "absent: needed only for closed-loop control");
    }
    // 7. Guidance: the file of the same name and any whose braking_decel names this vehicle.
    bool guidance = false;
    for (const auto& p : yaml_files(fs::path(root_) / "guidance")) {
      if (p.stem() != name && !names_file(read_text(p), file_name)) continue;
      guidance = true;
      attempt(p.string(), [&] {
        guidance::load_follower_node_params(config::Value::load_file(p.string()));
        return std::string("tiller-path-follower");
      });
    }
    if (!guidance) {
      note(fs::path(root_) / "guidance" / (name + ".yaml"),
           surface ? "absent: needed for autonomy (braking_decel from this vehicle)"
                   : "absent: needed only for autonomy");
    }
    // 8-9. Launch files that name one of this vehicle's files, and the teleop presets they start.
    mine.push_back(file_name);
    bool launched = false;
    for (const auto& p : yaml_files(fs::path(root_) / "launch")) {
      const std::string text = read_text(p);
      if (std::none_of(mine.begin(), mine.end(),
                       [&](const std::string& f) { return names_file(text, f); }))
        continue;
      launched = true;
      std::vector<std::string> presets;
      attempt(p.string(), [&] {
        const auto lf = launch::load_launch_file(p.string());
        for (const auto& proc : lf.processes) {
          if (fs::path(proc.command).filename() != "tiller-teleop") continue;
          for (std::size_t i = 0; i + 1 < proc.args.size(); ++i) {
            // ${NAME:-default}: the preset the environment picks, else the default (tools/rov-demo
            // sets sim_rov_demo.yaml's TILLER_ROV_TELEOP).
            if (proc.args[i] == "--config")
              presets.push_back(
                  (fs::path(lf.root) / launch::substitute(proc.args[i + 1], {})).string());
          }
        }
        return "tiller-launch: " + std::to_string(lf.processes.size()) + " processes";
      });
      for (const auto& t : presets) {
        attempt(t, [&] {
          const auto tp = load_teleop_file(t);
          return "tiller-teleop: " + std::to_string(tp.axes.size() + tp.button_axes.size()) +
                 " axis mappings";
        });
      }
    }
    if (!launched) note(fs::path(root_) / "launch", "no launch file uses " + name + "'s files");
    return std::move(report_);
  }

 private:
  bool names_vehicle(const fs::path& config_file) {
    try {
      const auto root = config::Value::load_file(config_file.string());
      const std::string v = root.string_or("vehicle", "");
      return !v.empty() && fs::path(v).filename() == fs::path(vehicle_).filename();
    } catch (const std::exception&) {
      // Not readable as YAML: it names this vehicle if its text does (then the load fails below).
      return names_file(read_text(config_file), fs::path(vehicle_).filename().string());
    }
  }

  std::string shown(const fs::path& p) const {
    const fs::path parent = fs::path(root_).parent_path();
    const std::string rel = fs::path(p).lexically_normal().lexically_relative(parent).string();
    return rel.empty() || rel.rfind("..", 0) == 0 ? p.string() : rel;
  }

  bool attempt(const std::string& file, const std::function<std::string()>& load) {
    try {
      report_.findings.push_back({Level::kOk, shown(file), load()});
      return true;
    } catch (const std::exception& e) {
      report_.findings.push_back({Level::kFail, shown(file), e.what()});
      return false;
    }
  }
  void missing(const fs::path& p, const std::string& why) {
    report_.findings.push_back({Level::kFail, shown(p), why + " (see docs/adding-a-vehicle.md)"});
  }
  void note(const fs::path& p, const std::string& why) {
    report_.findings.push_back({Level::kNote, shown(p), why});
  }

  std::string vehicle_;
  std::string root_;
  Report report_;
};

}  // namespace

bool Report::ok() const {
  return std::none_of(findings.begin(), findings.end(),
                      [](const Finding& f) { return f.level == Level::kFail; });
}

Report check_vehicle(const std::string& vehicle_file, const std::string& config_root) {
  return Checker(vehicle_file, config_root).run();
}

std::string format(const Report& r) {
  std::string out;
  for (const auto& f : r.findings) {
    out += f.level == Level::kOk ? "ok   " : f.level == Level::kNote ? "note " : "FAIL ";
    out += f.file + ": " + f.what + "\n";
  }
  return out;
}

}  // namespace tiller::vehiclecheck
