// The plants closed-loop tests and the benchmark run the autonomy against: the full stack
// (MixerNode + EscNode with the sim backend + SimNode) for the Otter and seed 004's X and H
// drive boats, and the stand-in Otter model (simple_plant.hpp).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mission/mission.hpp"
#include "runtime/node.hpp"

namespace tiller::test {

struct PlantSpec {
  std::string name;
  std::string control_file;
  std::string guidance_file;  // Tiller's defaults with this vehicle's braking deceleration
  std::string pose_channel;
  std::function<std::vector<std::unique_ptr<Node>>(const mission::Mission&, double, double)> make;
};

// The full stack for the Otter, seed004_usv_x and seed004_usv_h (pose: ground truth).
const std::vector<PlantSpec>& plants();
// The full stack for any vehicle with config/{control,guidance,esc,mixer} files of its name
// (wamv: not in plants(), whose tests predate its configs).
PlantSpec full_plant(const std::string& vehicle);
// The stand-in Otter model alone.
const PlantSpec& standin_plant();

}  // namespace tiller::test
