// A marine vessel's rigid-body dynamics (Fossen 2021, ch. 6 and 10), stepped by fixed-step RK4:
//
//   M nu_r_dot + C(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau_thrusters + tau_wind
//   nu_dot = nu_c_dot + nu_r_dot,  nu_r = nu - nu_c,  eta_dot = J(eta) nu
//
// State: eta = [n e d] m NED and [roll pitch yaw] rad (ZYX Euler, body -> NED), nu = [u v w p q r]
// body FRD over ground (m/s, rad/s). The water moves with `current_ned` (m/s, NED, irrotational,
// constant over a step): nu_c = [R^T v_c; 0], nu_c_dot = [-omega x nu_c; 0] (Fossen Property
// 10.1). C is the Coriolis-centripetal matrix of the total mass matrix (rigid body + added mass,
// Fossen Theorem 3.2; or of DynamicsParams::coriolis_mass_matrix if a file sets one), evaluated
// at the relative velocity; it is skew-symmetric, so it moves no energy. D is linear + quadratic
// diagonal damping (+ strip-theory cross-flow drag on surface vessels). g is the restoring force of
// weight and buoyancy (underwater_6dof only).
//
// Thrusters: each pushes along its unit direction at its position (body FRD from the reference
// point) with a thrust in N. The thrust follows its target with a first-order lag
// T_dot = (T_target - T) / tau, integrated exactly (the target is constant over a step, so the
// lag's closed form gives the thrust at each RK4 stage). No heap allocation after construction.
#pragma once

#include <array>
#include <span>

#include "sim/dynamics.hpp"

namespace tiller::sim {

inline constexpr int kMaxThrusters = 16;

struct ThrusterGeometry {
  Vector3 position = Vector3::Zero();    // m, body FRD from the reference point
  Vector3 direction = Vector3::UnitX();  // unit, body FRD, way a positive thrust pushes
};

// What the surroundings do during one step (NED, m/s).
struct Environment {
  Vector3 current_ned = Vector3::Zero();  // velocity of the water
  bool wind = false;                      // apply the wind model (surface vessels only)
  Vector3 wind_ned = Vector3::Zero();     // velocity of the air
  // An outside force on the vehicle at the reference point (N, NED): a test's disturbance (a
  // tether's pull, a bump). underwater_6dof only.
  Vector3 force_ned = Vector3::Zero();
};

class VesselModel {
 public:
  // Throws std::invalid_argument for more than kMaxThrusters thrusters or a zero direction.
  VesselModel(const DynamicsParams& params, std::span<const ThrusterGeometry> thrusters);

  // Sets the state; thrust and targets go to zero.
  void reset(const Vector6& eta, const Vector6& nu);
  // Target thrust of thruster i, N (the lag follows it). Non-finite values count as 0.
  void set_thrust_target(int i, double newtons);
  // Sets the current thrust (and target) directly, skipping the lag (tests, initial states).
  void set_thrust_now(int i, double newtons);

  // Advances by dt seconds (dt > 0) with `env` held over the step.
  void step(double dt, const Environment& env);

  const Vector6& eta() const { return eta_; }
  const Vector6& nu() const { return nu_; }
  // nu - nu_c for the given water velocity.
  Vector6 nu_relative(const Vector3& current_ned) const;
  int n_thrusters() const { return n_; }
  double thrust(int i) const { return thrust_[static_cast<std::size_t>(i)]; }
  double thrust_target(int i) const { return target_[static_cast<std::size_t>(i)]; }
  // Wrench of the present thrust, [X Y Z K M N].
  Vector6 thruster_wrench() const;
  // Column i: wrench of 1 N on thruster i.
  Vector6 thruster_column(int i) const { return b_[static_cast<std::size_t>(i)]; }

  // Kinetic energy 0.5 nu_r^T M nu_r (J) and potential energy of weight and buoyancy (J,
  // zero at the origin, level; underwater_6dof only).
  double kinetic_energy(const Vector3& current_ned) const;
  double potential_energy() const;

  // The right-hand side: (eta_dot, nu_dot) for a state, thruster wrench and environment.
  void derivative(const Vector6& eta, const Vector6& nu, const Vector6& tau, const Environment& env,
                  Vector6& eta_dot, Vector6& nu_dot) const;

  const DynamicsParams& params() const { return p_; }

 private:
  Vector6 damping(const Vector6& nu_r) const;
  Vector6 restoring(const Vector6& eta) const;
  Vector6 wind(const Vector6& eta, const Vector6& nu, const Vector3& wind_ned) const;

  DynamicsParams p_;
  bool surface_;
  Matrix6 m_inv_;
  Matrix3 m3_;      // surface: M over [u v r]
  Matrix3 c3_;      // surface: the Coriolis mass matrix over [u v r]
  Matrix3 m3_inv_;  // its inverse
  int n_ = 0;
  std::array<Vector6, kMaxThrusters> b_{};
  std::array<double, kMaxThrusters> thrust_{};
  std::array<double, kMaxThrusters> target_{};
  Vector6 eta_ = Vector6::Zero();
  Vector6 nu_ = Vector6::Zero();
};

// Rotation body -> NED for ZYX Euler angles (roll, pitch, yaw).
Matrix3 rotation_zyx(double roll, double pitch, double yaw);

}  // namespace tiller::sim
