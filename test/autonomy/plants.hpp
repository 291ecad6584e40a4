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
  std::string pose_channel;
  std::function<std::vector<std::unique_ptr<Node>>(const mission::Mission&, double, double)> make;
};

const std::vector<PlantSpec>& plants();

}  // namespace tiller::test
