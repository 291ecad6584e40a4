// tiller-nav's filter: an extended Kalman filter of a marine vehicle's position, body velocity and
// heading (docs/navigation.md has the models and their sources).
//
// State x (kStates = 12): [n e d] m, local NED about the datum; [u v w] m/s, velocity over ground
// in body FRD; psi rad, heading in (-pi, pi]; b_r rad/s, the gyro's yaw-rate bias; [b_ax b_ay]
// m/s^2, the accelerometer's forward and starboard biases; [c_n c_e] m/s, the water current's
// velocity over ground in NED (random walks, observed only through the sway constraint).
// Roll, pitch, the body rates [p q r] and the body acceleration are inputs (the IMU's own fused
// attitude, its gyro and its accelerometer less gravity), not states: a Motion sample, held
// between IMU samples.
// Process model (Fossen 2021, eq. 2.18 and 2.29: eta_dot = J(eta) nu): p_dot = R_zyx(phi, theta,
// psi) [u v w]; psi_dot = (q sin(phi) + (r - b_r) cos(phi)) / cos(theta); with the acceleration
// (an aided INS, Fossen 2021 ch. 14): u_dot = a_x - b_ax + r' v - q w, v_dot = a_y - b_ay - r' u
// + p w (r' = r - b_r: nu_dot = a - omega x nu in the body frame), else u and v random walks;
// w, b_r, b_ax, b_ay, c_n and c_e random walks; integrated with Euler steps, covariance
// P <- F P F^T + Q dt. The current enters no other state's model (the velocity is over ground):
// F is block diagonal, the first kCoreStates and the current, and predict keeps that structure.
// Measurements: north-east position (GNSS), north-east velocity (GNSS), body velocity (DVL),
// heading, depth, and the vertical velocity (a surface vehicle's w = 0), and the sway constraint
// (update_sway: a surface vessel's sway through the water is near 0 on straights). Each update
// gates on the normalised innovation squared NIS = y^T S^-1 y (chi-square with as many degrees of
// freedom as the measurement has): above the gate the measurement is refused and the state is left
// as it was. Joseph-form covariance update. Fixed-size Eigen matrices only: predict and update
// never allocate. While the current is uncorrelated with the rest (no sway update yet) and a
// measurement does not involve it, predict and update work on the first kCoreStates alone: the same
// arithmetic, bit for bit, as the filter without the current states. Time is a dt argument; nothing
// here reads a clock.
#pragma once

#include <Eigen/Core>

namespace tiller::nav {

inline constexpr int kStates = 12;
inline constexpr int kCoreStates = 10;  // all but the current
enum StateIndex : int {
  kN = 0,
  kE = 1,
  kD = 2,
  kU = 3,
  kV = 4,
  kW = 5,
  kPsi = 6,
  kBiasR = 7,
  kBiasAx = 8,
  kBiasAy = 9,
  kCurrentN = 10,
  kCurrentE = 11
};

using State = Eigen::Matrix<double, kStates, 1>;
using Covariance = Eigen::Matrix<double, kStates, kStates>;

// Process noise, as spectral densities (variance growth per second).
struct ProcessNoise {
  double position = 0.01;             // m^2/s: model error on the position kinematics
  double velocity_horizontal = 0.02;  // (m/s)^2/s: u and v random walk
  double velocity_vertical = 0.01;    // (m/s)^2/s: w random walk
  double heading = 1e-4;              // rad^2/s: gyro noise integrated into the heading
  double gyro_bias = 1e-8;            // (rad/s)^2/s: yaw-rate bias random walk
  double accel_bias = 3e-5;           // (m/s^2)^2/s: accelerometer bias random walk (x, y)
  double current = 1e-5;              // (m/s)^2/s: water current random walk (north, east)
};

// The IMU's part, held between its samples: roll and pitch (rad, ZYX Euler body->NED), the
// gyro's body rates (rad/s, FRD) and, when `accel` is set, the body's acceleration relative to
// NED in FRD (m/s^2: the specific force plus gravity, R^T [0 0 g], forward and starboard).
struct Motion {
  double roll = 0, pitch = 0;
  double p = 0, q = 0, r = 0;
  double ax = 0, ay = 0;
  bool accel = false;  // false: u and v are random walks (no accelerometer in the model)
  // With `accel`, also the vertical: w_dot = a_z + q u - p v (a_z m/s^2 down, no bias state: the
  // DVL's w corrects it); false: w is a random walk (a surface vehicle's w is held at 0).
  double az = 0;
  bool accel_vertical = false;
};

struct UpdateResult {
  bool accepted = false;
  double nis = 0;  // normalised innovation squared
};

class Ekf {
 public:
  explicit Ekf(const ProcessNoise& q = {});

  void reset(const State& x, const Covariance& p);
  const State& x() const { return x_; }
  const Covariance& P() const { return P_; }

  // Moves the state dt >= 0 seconds on with the motion held constant.
  void predict(double dt, const Motion& m);

  // A gate <= 0 lets every measurement in. Variances and covariances in SI units squared.
  UpdateResult update_position_ne(const Eigen::Vector2d& z, const Eigen::Matrix2d& r, double gate);
  UpdateResult update_velocity_ne(const Eigen::Vector2d& z, const Eigen::Matrix2d& r,
                                  const Motion& m, double gate);
  UpdateResult update_heading(double z, double variance, double gate);
  UpdateResult update_depth(double z, double variance, double gate);
  UpdateResult update_vertical_velocity(double z, double variance, double gate);
  // A DVL's bottom-track velocity: [u v w] over ground in body FRD (m/s), measured directly
  // (h selects the velocity states), with its 3x3 covariance; 3 degrees of freedom.
  UpdateResult update_velocity_body(const Eigen::Vector3d& z, const Eigen::Matrix3d& r,
                                    double gate);
  // The sway constraint, a pseudo-measurement 0 = v - v_c, v_c = -sin(psi) c_n + cos(psi) c_e
  // (the current's starboard component: the body's sway through the water is 0), with the
  // 1-sigma sway_std(std_mps, rate_gain_s, r - b_r, u) (m/s) for the motion's yaw rate r.
  // Roll and pitch are taken as 0 (a surface vessel).
  UpdateResult update_sway(const Motion& m, double std_mps, double rate_gain_s, double gate);
  // The constraint's 1-sigma, m/s: std_mps + rate_gain_s |r| |u| (r rad/s, u m/s; a turning hull
  // sways, roughly in proportion to its yaw rate and speed).
  static double sway_std(double std_mps, double rate_gain_s, double r, double u);

  // Sets one part of the state from a measurement (its first value): the part's covariance
  // becomes `variance` on the diagonal, its correlations with the rest 0.
  void set_position_ne(double n, double e, double variance);
  void set_velocity_body(double u, double v, double variance);
  void set_heading(double psi, double variance);
  void set_depth(double d, double variance);
  void set_state(int index, double value, double variance);
  // Keeps an unobserved state's variance at most `cap` (an ROV's north, east and velocity with
  // no position source would otherwise grow without bound): a capped state is decorrelated.
  void cap_variance(int index, double cap);

  // Rotation body FRD -> NED, R_zyx(phi, theta, psi) (Fossen 2021, eq. 2.18).
  static Eigen::Matrix3d rotation(double roll, double pitch, double yaw);

 private:
  template <int M>
  UpdateResult update(const Eigen::Matrix<double, M, 1>& y,
                      const Eigen::Matrix<double, M, kStates>& h,
                      const Eigen::Matrix<double, M, M>& r, double gate);
  // The update on the first N states (N = kStates: all of them; kCoreStates: the current left as
  // it is, for an h without current columns while the current is uncorrelated).
  template <int N, int M>
  UpdateResult update_first(const Eigen::Matrix<double, M, 1>& y,
                            const Eigen::Matrix<double, M, kStates>& h,
                            const Eigen::Matrix<double, M, M>& r, double gate);
  void set_block(int index, int n, double variance);
  // True while the current's covariance has no correlation with the other states.
  bool current_apart() const;

  ProcessNoise q_;
  State x_ = State::Zero();
  Covariance P_ = Covariance::Identity();
};

}  // namespace tiller::nav
