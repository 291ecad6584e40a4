// Helpers for the allocation tests: preset loading and seeded random wrenches.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "allocation/allocator.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller::test {

inline const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = {
      "seed000_rov4",  "seed001_rov6", "seed004_usv_x", "seed004_usv_x_table",
      "seed004_usv_h", "otter",        "wamv"};
  return names;
}

inline Vehicle preset(const std::string& name) {
  return load_vehicle_file(std::string(TILLER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml");
}

// Random wrench on the actuated axes, each component scaled by that axis' largest value.
inline Wrench random_wrench(const Allocator& a, std::mt19937& rng, double size) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Wrench w = Wrench::Zero();
  for (int ax = 0; ax < 6; ++ax)
    if (!a.unactuated()[static_cast<std::size_t>(ax)])
      w(ax) = size * u(rng) * std::max(a.axis_max(ax, 1), a.axis_max(ax, -1));
  return w;
}

// Same vehicle with another strategy (and the default priority X Y Z N M K when needed).
inline Vehicle with_strategy(Vehicle v, Strategy s) {
  v.allocation.strategy = s;
  if (s == Strategy::kPrioritised && v.allocation.priority.empty())
    v.allocation.priority = {{0}, {1}, {2}, {5}, {4}, {3}};
  return v;
}

}  // namespace tiller::test
