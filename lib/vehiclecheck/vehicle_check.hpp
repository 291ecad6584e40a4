// Checks every file a vehicle needs, together (docs/adding-a-vehicle.md, "The checklist"): the
// vehicle file and its simulator section, the mixer and ESC configs that name it, the controller
// and guidance files of the same name, and the launch files that use them with their teleop
// presets. Each file is loaded by the same loader its program uses; no LCM is opened, no device.
#pragma once

#include <string>
#include <vector>

namespace tiller::vehiclecheck {

enum class Level { kOk, kNote, kFail };

struct Finding {
  Level level = Level::kOk;
  std::string file;  // the file checked (or that should exist), relative to the config root
  std::string what;  // what was found: the program that reads it, or the error
};

struct Report {
  std::vector<Finding> findings;
  bool ok() const;  // no kFail
};

// vehicle_file: the vehicle description (config/vehicles/NAME.yaml). config_root: the folder
// holding vehicles/, mixer/, esc/, control/, guidance/, teleop/, launch/ (the repository's
// config/). Required: the vehicle file with a `dynamics:` section, at least one mixer config
// and one ESC config naming it (by file name; each must then load and name this very file).
// Checked when present: config/control/NAME.yaml, config/guidance/NAME.yaml, guidance files
// whose braking_decel names the vehicle, launch files that name one of the vehicle's files,
// and the teleop presets those launch files start.
Report check_vehicle(const std::string& vehicle_file, const std::string& config_root);

// One line per finding: "ok   FILE: what", "note FILE: what", "FAIL FILE: what".
std::string format(const Report& r);

}  // namespace tiller::vehiclecheck
