// Parameters of a vessel's rigid-body dynamics (Fossen's model), as read from the `dynamics:`
// section of a vehicle file (config/vehicles/<name>.yaml). Plain numbers; the model never sees
// YAML.
//
// Frames and units: body FRD about the vehicle's reference point (the point the vehicle file's
// thruster positions are measured from), nu = [u v w p q r] (m/s, rad/s), tau = [X Y Z K M N]
// (N, N m). Every matrix and vector here is in that order, SI units.
//
// Two kinds of model:
//   surface_3dof:    surge, sway, yaw (u, v, r). The 3x3 mass matrix (rigid body + added mass)
//                    is given directly; w, p, q, heave, roll and pitch stay zero.
//   underwater_6dof: all six degrees of freedom, with restoring forces from weight and buoyancy
//                    acting at the centres of gravity and buoyancy.
#pragma once

#include <string>

#include <Eigen/Dense>

namespace tiller::config {
class Value;
}

namespace tiller::sim {

using Vector3 = Eigen::Vector3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix3 = Eigen::Matrix3d;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

enum class ModelKind { kSurface3Dof, kUnderwater6Dof };

// Cross-flow drag by strip theory (Fossen, Handbook of Marine Craft Hydrodynamics, sec. 6.4.3):
// quadratic sway force and yaw moment from the hull's strips, each seeing v + x r.
struct CrossFlowDrag {
  bool enabled = false;
  double length_m = 0;  // hull length, strips from -L/2 to +L/2
  double draft_m = 0;   // draft T
  double cd = 0;        // 2-D drag coefficient of the section (Hoerner)
  int strips = 20;
};

struct DynamicsParams {
  ModelKind kind = ModelKind::kSurface3Dof;
  // Total mass matrix M = M_RB + M_A (symmetric, positive definite). For surface_3dof only the
  // rows and columns of u, v and r are meaningful (the others hold 1 on the diagonal).
  Matrix6 mass_matrix = Matrix6::Identity();
  // Mass matrix whose Coriolis-centripetal forces are modelled (Fossen Theorem 3.2 applied to
  // it). Default: mass_matrix (rigid body and added mass); a surface_3dof file may set
  // `coriolis_mass_matrix` to model a different part. No shipped vehicle file sets it (the
  // Otter's keeps the full M; docs/algorithms.md, "Vehicle models", says why and what otter.py
  // does).
  Matrix6 coriolis_mass_matrix = Matrix6::Identity();
  // Damping: force_i = -(linear_i + quadratic_i |nu_r,i|) nu_r,i (both >= 0).
  Vector6 linear_damping = Vector6::Zero();
  Vector6 quadratic_damping = Vector6::Zero();
  // Point (body FRD from the reference point) where the translational damping acts; it sees
  // the velocity v + omega x r_d there and its force makes the moment r_d x F. Zero (Fossen's
  // usual model) puts all damping at the reference point. underwater_6dof only.
  Vector3 damping_center_m = Vector3::Zero();
  CrossFlowDrag cross_flow;
  double water_density_kg_m3 = 1025.0;
  double gravity_m_s2 = 9.81;
  // Restoring forces (underwater_6dof only). W = m g, B = rho g volume.
  double mass_kg = 0;
  double weight_n = 0;
  double buoyancy_n = 0;
  Vector3 center_of_gravity_m = Vector3::Zero();   // r_g, body FRD from the reference point
  Vector3 center_of_buoyancy_m = Vector3::Zero();  // r_b
  // First-order lag of every thruster's thrust, seconds (0 = none).
  double thruster_time_constant_s = 0.1;
  // Optional `simulator_thrust_curve`: a lib/vehicle preset name (t200_12v, t200_16v, ...) that
  // the simulator uses for every thruster instead of the thrusters' own `curve`. For a vehicle
  // whose mixer keeps a simplified curve on purpose (seed 000's linear 30 N, so its a/b
  // arithmetic is reproduced exactly) while the motors are T200s. Empty: the thrusters' curves.
  std::string simulator_thrust_curve;
  // Wind (surface_3dof only; VRX's model): X = c0 uw|uw|, Y = c1 vw|vw|, N = -2 c2 uw vw, with
  // (uw, vw) the relative wind in the body frame (m/s). Zero: no wind force.
  Vector3 wind_coefficients = Vector3::Zero();
  std::string source;  // where the numbers come from (free text from the file)
};

// Reads a vehicle file's `dynamics:` section strictly (unknown, missing or out-of-range keys
// throw config::Error naming the file, line and key).
DynamicsParams load_dynamics(const config::Value& dynamics);

// Skew-symmetric cross-product matrix: S(a) b = a x b.
inline Matrix3 skew(const Vector3& a) {
  Matrix3 s;
  s << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return s;
}

// Rigid-body mass matrix about the reference point for a body of mass m, inertia I_g about
// its centre of gravity (principal axes along body axes), CG at r_g (Fossen eq. 3.44).
Matrix6 rigid_body_mass_matrix(double mass, const Vector3& inertia_cg, const Vector3& r_g);

}  // namespace tiller::sim
