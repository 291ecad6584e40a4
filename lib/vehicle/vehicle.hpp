// A vehicle's thruster layout and how its mixer allocates, as read from config/vehicles/*.yaml.
//
// Frames and units: positions in m from the centre of gravity, body FRD (x forward, y right,
// z down); `direction` is the unit vector (FRD) along which the thruster pushes the VEHICLE for
// a positive thruster command; thrust limits in N (positive numbers); wrench axes
// [X Y Z K M N] (N, N m), index 0..5.
//
// Reversal (docs/escs-and-wiring.md): `reversed: true` means the motor is wired or propped
// backwards, so a positive motor (ESC) command pushes the vehicle AGAINST `direction`. Tiller's
// thruster command keeps "positive = along direction"; tiller-esc flips the hardware sign. So
// when reversed, pushing along `direction` uses the motor's (weaker) reverse side. The helpers
// thrust_min/max, thrust_from_command and command_from_thrust already account for it: the
// mixer and the simulator (after undoing the ESC's flip) use them and nothing else.
//
// The loader is strict: unknown keys, missing keys, wrong types, bad ranges, a non-unit
// direction, duplicate names or limits beyond the curve stop with file, key and expectation.
// The `dynamics:` section belongs to lib/sim and is only marked used here.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/config.hpp"
#include "vehicle/thrust_curve.hpp"

namespace tiller {

inline constexpr int kMaxThrusters = 16;
inline constexpr std::array<const char*, 6> kAxisNames = {"X", "Y", "Z", "K", "M", "N"};

// Index 0..5 of an axis name ("X".."N"), -1 if unknown.
int axis_index(const std::string& name);

struct Thruster {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();    // m, FRD, from the CG
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, FRD
  double max_forward_n = 0;                              // motor's forward side limit, N (> 0)
  double max_reverse_n = 0;                              // motor's reverse side limit, N (> 0)
  ThrustCurve curve;                                     // motor command -> motor thrust
  std::string group;  // thrusters of one group are scaled together
  bool reversed = false;

  // Allowed thrust along `direction`, N: [thrust_min() < 0, thrust_max() > 0].
  double thrust_min() const { return reversed ? -max_forward_n : -max_reverse_n; }
  double thrust_max() const { return reversed ? max_reverse_n : max_forward_n; }
  // Thruster command (Tiller convention, + = along direction) -> thrust along direction, N.
  double thrust_from_command(double u) const {
    return reversed ? -curve.thrust(-u) : curve.thrust(u);
  }
  // Thrust along direction, N -> thruster command in [-1, 1].
  double command_from_thrust(double f) const {
    return reversed ? -curve.command(-f) : curve.command(f);
  }
  // Column of the effectiveness matrix: [direction; position x direction].
  Eigen::Matrix<double, 6, 1> wrench_per_newton() const;
};

enum class Strategy { kDirectionPreserving, kPrioritised, kClip };
const char* strategy_name(Strategy s);

struct AllocationSpec {
  Strategy strategy = Strategy::kDirectionPreserving;
  // Prioritised: levels of axis indices, first level first; axes of one level are scaled
  // together. Every axis appears exactly once (the loader appends missing ones in X..N order).
  std::vector<std::vector<int>> priority;
  // Explicit mixing matrix (seed tables) instead of geometry: s = M * tau_norm (see
  // matrix_commands for what s is); tau_norm_j = tau_j / full_scale_j (full_scale computed from
  // the geometry when the allocator is built). Empty when the geometry is used.
  std::vector<int> matrix_axes;  // axis indices of M's columns
  Eigen::MatrixXd matrix;        // n_thrusters x matrix_axes.size()
  bool has_matrix() const { return !matrix_axes.empty(); }
  // `mixing.units`: what a row entry is. thrust_fraction: s_i is a fraction of the thruster's
  // forward limit (thrust_i = s_i * max_forward_n, linear in the demand). command: s_i is the
  // thruster command itself (what seeds 001 and 004 compute: duty cycle / motor command), sent
  // as it is; thrust_i = the curve's thrust at s_i.
  bool matrix_commands = false;
  // `mixing.normalise`: ratio-keeping normalisation per group. above_one: divide the group's
  // values by the largest magnitude only when it exceeds 1 (its limit); always: divide so that
  // the largest magnitude is exactly 1 (scaling small demands up).
  bool normalise_always = false;
  std::string matrix_key;  // "x_drive" or "rows", for messages
};

struct Vehicle {
  std::string name;
  std::string description;
  std::string source_file;  // where it was loaded from, for messages
  std::vector<Thruster> thrusters;
  AllocationSpec allocation;

  int size() const { return static_cast<int>(thrusters.size()); }
  int index_of(const std::string& thruster_name) const;  // -1 if absent
  // 6 x n effectiveness matrix B: wrench = B * thrust.
  Eigen::MatrixXd effectiveness() const;
};

// Loads a vehicle from a parsed document (checks every key it owns; marks `dynamics` used).
// Throws config::Error.
Vehicle load_vehicle(const config::Value& root);
// Loads and checks a file (also calls check_all_used on the whole document).
Vehicle load_vehicle_file(const std::string& path);

// Seed 004's X-drive table in Tiller's FRD convention, columns [X Y N], rows [LF RF LR RR]:
// the seed (ROS, FLU, yaw counter-clockwise) writes LF = -Fy+Fx-T, RF = Fy+Fx+T,
// LR = k*Fy+Fx-T, RR = -k*Fy+Fx+T; with Y = -Fy and N = -T that is
// LF = X+Y+N, RF = X-Y-N, LR = X-kY+N, RR = X+kY-N.
Eigen::Matrix<double, 4, 3> x_drive_table(double k);

}  // namespace tiller
