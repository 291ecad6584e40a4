// tiller-check-vehicle: loads every file a vehicle needs (vehicle and simulator section, mixer,
// ESC, controller, guidance, launch files, teleop presets) together, without LCM or devices, and
// says which is missing or wrong. See lib/vehiclecheck/vehicle_check.hpp, docs/adding-a-vehicle.md.
#include <filesystem>
#include <iostream>

#include "runtime/app.hpp"
#include "vehiclecheck/vehicle_check.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  app::Spec spec{"tiller-check-vehicle",
                 "Checks the files a vehicle needs together (vehicle, mixer, ESC, control, "
                 "guidance, launch, teleop); exit 1 naming what is missing or wrong.",
                 "",
                 {{"vehicle", "FILE", "the vehicle file, e.g. config/vehicles/otter.yaml", ""},
                  {"config-root", "DIR",
                   "the folder with vehicles/, mixer/, esc/, ... (default: the vehicle file's "
                   "folder's parent)",
                   ""}}};
  spec.takes_config = false;
  spec.takes_lcm_url = false;
  const auto args = app::parse(argc, argv, spec);
  return app::guarded_main("tiller-check-vehicle", [&] {
    if (!args.positional.empty())
      throw std::runtime_error("unexpected argument '" + args.positional[0] +
                               "': give the vehicle file with --vehicle FILE");
    const std::string vehicle = app::resolve_path(args.get("vehicle"));
    if (vehicle.empty()) throw std::runtime_error("--vehicle FILE is required");
    if (!std::filesystem::exists(vehicle)) throw std::runtime_error(vehicle + ": no such file");
    std::string root = args.get("config-root");
    if (root.empty())
      root = std::filesystem::absolute(vehicle).lexically_normal().parent_path().parent_path();
    const auto report = vehiclecheck::check_vehicle(vehicle, root);
    std::cout << vehiclecheck::format(report);
    std::cout << "tiller-check-vehicle: " << vehicle << (report.ok() ? ": OK" : ": FAILED") << "\n";
    return report.ok() ? 0 : 1;
  });
}
