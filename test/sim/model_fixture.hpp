// Test fixtures for the vessel model: the `dynamics:` sections of the reference vehicles
// (the same numbers as config/vehicles/*.yaml; sources in ../shared/design/vehicles.md) and
// simple thruster layouts, so the model's tests do not depend on the vehicle loader.
#pragma once

#include <vector>

#include "core/config.hpp"
#include "sim/dynamics.hpp"
#include "sim/vessel_model.hpp"

namespace tiller::sim::test {

inline const char* kOtterDynamics = R"(
model: surface_3dof
mass_matrix: [[85.5, 0, 0], [0, 162.5, 12.25], [0, 12.25, 42.65]]
linear_damping: [77.55, 162.5, 42.65]
quadratic_damping: [0, 0, 426.5]
cross_flow_drag: {length_m: 2.0, draft_m: 0.195, cd: 1.0}
water_density_kg_m3: 1026
thruster_time_constant_s: 0.1
wind_coefficients: [0.5, 0.5, 0.33]
)";

// The Otter as Fossen's otter.py has it: C of the rigid body alone (m = 80 kg, m x_g = 12.25),
// the added-mass (Munk) moment neglected. Not what config/vehicles/otter.yaml uses today.
inline const char* kOtterRigidCoriolisDynamics = R"(
model: surface_3dof
mass_matrix: [[85.5, 0, 0], [0, 162.5, 12.25], [0, 12.25, 42.65]]
coriolis_mass_matrix: [[80, 0, 0], [0, 80, 12.25], [0, 12.25, 15.8]]
linear_damping: [77.55, 162.5, 42.65]
quadratic_damping: [0, 0, 426.5]
cross_flow_drag: {length_m: 2.0, draft_m: 0.195, cd: 1.0}
water_density_kg_m3: 1026
thruster_time_constant_s: 0.1
)";

inline const char* kWamvDynamics = R"(
model: surface_3dof
mass_matrix: [[180, 0, 0], [0, 180, 0], [0, 0, 446]]
linear_damping: [51.3, 40.0, 400.0]
quadratic_damping: [72.4, 0, 0]
thruster_time_constant_s: 0.1
wind_coefficients: [0.5, 0.5, 0.33]
)";

inline const char* kBlueRov2Dynamics = R"(
model: underwater_6dof
mass_kg: 13.5
inertia_kg_m2: [0.26, 0.23, 0.37]
center_of_gravity_m: [0, 0, 0]
center_of_buoyancy_m: [0, 0, -0.10]
displaced_volume_m3: 0.0134
water_density_kg_m3: 1000
added_mass: [6.36, 7.12, 18.68, 0.189, 0.135, 0.222]
linear_damping: [13.7, 0, 33.0, 0, 0.8, 0]
quadratic_damping: [141, 217, 190, 1.19, 0.47, 1.50]
damping_center_m: [0, 0, 0.0425]
thruster_time_constant_s: 0.05
)";

inline DynamicsParams dynamics_from(const char* yaml) {
  const auto v = config::Value::parse(yaml, "fixture");
  auto p = load_dynamics(v);
  v.check_all_used();
  return p;
}

// Two propellers at y = -+0.395 m (port, starboard), pushing forward.
inline std::vector<ThrusterGeometry> otter_thrusters() {
  return {{Vector3(-0.9, -0.395, 0), Vector3::UnitX()},
          {Vector3(-0.9, 0.395, 0), Vector3::UnitX()}};
}
// Two aft engines at (-2.37, -+1.03) m.
inline std::vector<ThrusterGeometry> wamv_thrusters() {
  return {{Vector3(-2.37, -1.03, 0), Vector3::UnitX()},
          {Vector3(-2.37, 1.03, 0), Vector3::UnitX()}};
}
// BlueROV2-like: four horizontal at 45 deg, two vertical pushing down (+z).
inline std::vector<ThrusterGeometry> rov_thrusters() {
  const double c = std::sqrt(0.5);
  return {{Vector3(0.156, -0.111, 0.085), Vector3(c, c, 0)},
          {Vector3(0.156, 0.111, 0.085), Vector3(c, -c, 0)},
          {Vector3(-0.156, -0.111, 0.085), Vector3(c, -c, 0)},
          {Vector3(-0.156, 0.111, 0.085), Vector3(c, c, 0)},
          {Vector3(0, -0.111, 0), Vector3::UnitZ()},
          {Vector3(0, 0.111, 0), Vector3::UnitZ()}};
}

}  // namespace tiller::sim::test
