#include "plants.hpp"

#include "simple_plant.hpp"

namespace tiller::test {

const std::vector<PlantSpec>& plants() {
  static const std::vector<PlantSpec> p = [] {
    std::vector<PlantSpec> v;
    v.push_back({"otter-standin", "config/control/otter.yaml", "TILLER_ODOMETRY",
                 [](const mission::Mission& m, double speed, double from) {
                   std::vector<std::unique_ptr<Node>> n;
                   const auto s = m.start.value_or(mission::MissionPoint{});
                   n.push_back(
                       std::make_unique<SimplePlant>(speed, from, s.north, s.east, s.heading));
                   return n;
                 }});
    return v;
  }();
  return p;
}

}  // namespace tiller::test
