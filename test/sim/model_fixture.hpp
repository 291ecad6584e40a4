// Test fixtures for the vessel model: the reference vehicles exactly as the simulator runs them,
// loaded from the shipped config/vehicles/<name>.yaml (dynamics and thruster geometry, through
// load_sim_vehicle_file, every key checked; sources in docs/adding-a-vehicle.md). The
// validation tests therefore check the files themselves, not copies of their numbers.
#pragma once

#include <string>
#include <vector>

#include "core/config.hpp"
#include "sim/dynamics.hpp"
#include "sim/sim_node.hpp"
#include "sim/vessel_model.hpp"

namespace tiller::sim::test {

inline std::string vehicle_file(const std::string& name) {
  return std::string(TILLER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml";
}

inline SimVehicle shipped(const std::string& name) {
  return load_sim_vehicle_file(vehicle_file(name));
}

inline DynamicsParams dynamics_of(const std::string& name) {
  return shipped(name).dynamics;
}

// Position and direction of each thruster, in the file's order.
inline std::vector<ThrusterGeometry> geometry_of(const std::string& name) {
  std::vector<ThrusterGeometry> g;
  for (const auto& t : shipped(name).vehicle.thrusters) g.push_back({t.position, t.direction});
  return g;
}

inline VesselModel model_of(const std::string& name) {
  return VesselModel(dynamics_of(name), geometry_of(name));
}

// The Otter with the Coriolis terms of the rigid body alone (m = 80 kg, M23 = 12.25, Iz = 15.8):
// no added-mass (Munk) yaw moment, like otter.py, which zeroes C_A's yaw-row u and v entries;
// but unlike otter.py also without C_A's surge and sway terms (Tiller's coriolis_mass_matrix
// cannot zero single entries). Not what config/vehicles/otter.yaml uses.
inline DynamicsParams otter_rigid_coriolis() {
  DynamicsParams p = dynamics_of("otter");
  constexpr int idx[3] = {0, 1, 5};
  const double c[3][3] = {{80, 0, 0}, {0, 80, 12.25}, {0, 12.25, 15.8}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.coriolis_mass_matrix(idx[i], idx[j]) = c[i][j];
  return p;
}

// A `dynamics:` section given as text (loader tests).
inline DynamicsParams dynamics_from(const char* yaml) {
  const auto v = config::Value::parse(yaml, "fixture");
  auto p = load_dynamics(v);
  v.check_all_used();
  return p;
}

}  // namespace tiller::sim::test
