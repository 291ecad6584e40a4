// tiller-tune's model identification: from a record of what the thrusters were told and how
// the vehicle moved, the per-axis model
//
//   m dnu/dt + d nu + d2 |nu| nu - g = tau_f,      T dtau_f/dt = tau - tau_f
//
// for the axes surge (u), sway (v), heave (w) and yaw (r): m the mass with added mass (kg; yaw:
// the inertia, kg m^2), d the linear damping (N s/m; N m s/rad), d2 the quadratic damping
// (N s^2/m^2; N m s^2/rad^2), g a constant force (heave only: weight less buoyancy, N, + down),
// tau the thrusters' wrench on that axis (the targets the ESC output gives, through the vehicle's
// thrust curves and geometry) and T the thrusters' time constant (s), one for all thrusters.
// Body FRD, velocities over ground (identify in still water).
//
// Method (Eigen least squares, no differentiation of noisy velocities): integrated over a window
// [a, b] the model is linear in (m, d, d2, g):
//   m (nu_b - nu_a) + d int nu + d2 int |nu| nu - g (t_b - t_a) = int tau_f,
// with int tau_f exact for the targets held between ESC outputs (first-order lag in closed form)
// and the velocity integrals trapezoidal. Windows are consecutive and do not overlap; an axis
// uses the windows in which it alone is driven (the other axes' wrench and velocity below the
// options' limits; heave's velocity excepted, since a buoyant ROV rises whenever the pilot gives
// no heave), so a yaw turn does not pass for surge drag. T minimises the sum over axes of
// the unexplained fraction of each axis's regression (a scan over log T, then golden section).
// Each parameter comes with its standard deviation sigma^2 (A^T A)^-1 (sigma^2 the residual
// variance); T with its 95 % interval from the profile of the residual (likelihood ratio,
// chi-square 3.84). An axis with fewer windows than parameters + 3, or not driven, is reported
// as not identified with the reason. Pure: same record, same result, bit for bit.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

namespace tiller::tune {

enum Axis { kSurge = 0, kSway = 1, kHeave = 2, kYaw = 3 };
inline constexpr int kAxes = 4;
inline constexpr int kNuIndex[kAxes] = {0, 1, 2, 5};      // index in nu = [u v w p q r]
inline constexpr int kWrenchIndex[kAxes] = {0, 1, 2, 5};  // index in [X Y Z K M N]
inline constexpr const char* kAxisName[kAxes] = {"surge", "sway", "heave", "yaw"};

using Wrench = Eigen::Matrix<double, 6, 1>;

struct MotionSample {
  double t = 0;                // s
  std::array<double, 6> nu{};  // [u v w] m/s, [p q r] rad/s, body FRD over ground
};

// The thrusters' wrench targets from time t on (until the next), [X Y Z K M N] N, N m.
struct WrenchTarget {
  double t = 0;  // s
  Wrench tau = Wrench::Zero();
};

struct Record {
  std::vector<MotionSample> motion;   // time-ordered
  std::vector<WrenchTarget> targets;  // time-ordered
};

struct IdentifyOptions {
  double window_s = 1.0;         // s: length of one regression window
  double driven_n = 5.0;         // N (N m): an axis is driven above this wrench target
  double quiet_wrench_n = 2.0;   // N (N m): other axes' targets below this in its windows
  double quiet_velocity = 0.05;  // m/s, rad/s: other axes' velocities below this
  double time_constant_min_s = 0.005, time_constant_max_s = 2.0;
  bool heave_bias = true;  // heave: identify g (weight less buoyancy)
};

struct Estimate {
  double value = 0;
  double std = 0;  // one standard deviation
};

struct AxisModel {
  bool identified = false;
  std::string why;  // not identified: why
  Estimate mass, linear, quadratic, bias;
  int windows = 0;         // regression rows
  double unexplained = 0;  // residual sum of squares / sum of squares of int tau_f
};

struct Identified {
  std::array<AxisModel, kAxes> axis;
  double time_constant = 0;                              // s
  double time_constant_low = 0, time_constant_high = 0;  // s: 95 % interval
  int samples = 0;
};

Identified identify(const Record& r, const IdentifyOptions& o = {});

// The integrated regression of one axis for a given time constant (for tests and the profile):
// rows [nu_b - nu_a, int nu, int |nu| nu, -(t_b - t_a)] and right-hand side int tau_f.
struct Regression {
  Eigen::MatrixXd a;
  Eigen::VectorXd y;
};
Regression regression(const Record& r, int axis, double time_constant, const IdentifyOptions& o);

}  // namespace tiller::tune
