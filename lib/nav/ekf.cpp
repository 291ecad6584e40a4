#include "nav/ekf.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "core/angles.hpp"

namespace tiller::nav {

namespace {
// cos(theta) floor in the Euler-rate kinematics: |pitch| <= ~85 deg (the ZYX singularity at 90).
constexpr double kMinCosPitch = 0.087;
constexpr int kCore = kCoreStates;
using CoreCovariance = Eigen::Matrix<double, kCore, kCore>;
}  // namespace

Ekf::Ekf(const ProcessNoise& q) : q_(q) {}

void Ekf::reset(const State& x, const Covariance& p) {
  x_ = x;
  x_(kPsi) = wrap_pi(x_(kPsi));
  P_ = p;
}

Eigen::Matrix3d Ekf::rotation(double roll, double pitch, double yaw) {
  const double cf = std::cos(roll), sf = std::sin(roll);
  const double ct = std::cos(pitch), st = std::sin(pitch);
  const double cp = std::cos(yaw), sp = std::sin(yaw);
  Eigen::Matrix3d r;
  r << cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st,  //
      sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf,   //
      -st, ct * sf, ct * cf;
  return r;
}

void Ekf::predict(double dt, const Motion& m) {
  if (!(dt > 0)) return;
  const Eigen::Matrix3d r = rotation(m.roll, m.pitch, x_(kPsi));
  const Eigen::Vector3d v = x_.segment<3>(kU);
  const Eigen::Vector3d pdot = r * v;
  // dR/dpsi: row 0 -> -row 1, row 1 -> row 0, row 2 -> 0; applied to v.
  const Eigen::Vector3d dp_dpsi(-pdot(1), pdot(0), 0.0);
  const double cf = std::cos(m.roll);
  const double ct = std::max(std::cos(m.pitch), kMinCosPitch);
  const double rc = m.r - x_(kBiasR);
  const double psi_dot = (m.q * std::sin(m.roll) + rc * cf) / ct;

  // The Jacobian of the first kCoreStates; the current's block is the identity.
  CoreCovariance f = CoreCovariance::Identity();
  f.block<3, 3>(kN, kU) = r * dt;
  f.block<3, 1>(kN, kPsi) = dp_dpsi * dt;
  f(kPsi, kBiasR) = -cf / ct * dt;

  x_.segment<3>(kN) += pdot * dt;
  x_(kPsi) = wrap_pi(x_(kPsi) + psi_dot * dt);
  if (m.accel) {
    // nu_dot = a - omega x nu, forward and starboard; omega = [p q r - b_r].
    const double udot = m.ax - x_(kBiasAx) + rc * v(1) - m.q * v(2);
    const double vdot = m.ay - x_(kBiasAy) - rc * v(0) + m.p * v(2);
    f(kU, kV) = rc * dt;
    f(kU, kW) = -m.q * dt;
    f(kU, kBiasR) = -v(1) * dt;
    f(kU, kBiasAx) = -dt;
    f(kV, kU) = -rc * dt;
    f(kV, kW) = m.p * dt;
    f(kV, kBiasR) = v(0) * dt;
    f(kV, kBiasAy) = -dt;
    x_(kU) += udot * dt;
    x_(kV) += vdot * dt;
    if (m.accel_vertical) {
      const double wdot = m.az + m.q * v(0) - m.p * v(1);
      f(kW, kU) = m.q * dt;
      f(kW, kV) = -m.p * dt;
      x_(kW) += wdot * dt;
    }
  }

  const CoreCovariance pc = P_.topLeftCorner<kCore, kCore>();
  P_.topLeftCorner<kCore, kCore>() = f * pc * f.transpose();
  if (!current_apart()) {
    const Eigen::Matrix<double, kCore, 2> cross = f * P_.topRightCorner<kCore, 2>();
    P_.topRightCorner<kCore, 2>() = cross;
    P_.bottomLeftCorner<2, kCore>() = cross.transpose();
  }
  P_(kN, kN) += q_.position * dt;
  P_(kE, kE) += q_.position * dt;
  P_(kD, kD) += q_.position * dt;
  P_(kU, kU) += q_.velocity_horizontal * dt;
  P_(kV, kV) += q_.velocity_horizontal * dt;
  P_(kW, kW) += q_.velocity_vertical * dt;
  P_(kPsi, kPsi) += q_.heading * dt;
  P_(kBiasR, kBiasR) += q_.gyro_bias * dt;
  P_(kBiasAx, kBiasAx) += q_.accel_bias * dt;
  P_(kBiasAy, kBiasAy) += q_.accel_bias * dt;
  P_(kCurrentN, kCurrentN) += q_.current * dt;
  P_(kCurrentE, kCurrentE) += q_.current * dt;
}

bool Ekf::current_apart() const {
  return P_.topRightCorner<kCore, 2>().isZero(0.0);
}

template <int M>
UpdateResult Ekf::update(const Eigen::Matrix<double, M, 1>& y,
                         const Eigen::Matrix<double, M, kStates>& h,
                         const Eigen::Matrix<double, M, M>& r, double gate) {
  // The current, uncorrelated and not measured, keeps its value and covariance (K's rows for it
  // would be 0): the first kCoreStates alone, the same numbers as the 10-state filter's.
  if (current_apart() && h.template rightCols<2>().isZero(0.0))
    return update_first<kCore, M>(y, h, r, gate);
  return update_first<kStates, M>(y, h, r, gate);
}

template <int N, int M>
UpdateResult Ekf::update_first(const Eigen::Matrix<double, M, 1>& y,
                               const Eigen::Matrix<double, M, kStates>& hf,
                               const Eigen::Matrix<double, M, M>& r, double gate) {
  using Square = Eigen::Matrix<double, N, N>;
  const Square p = P_.template topLeftCorner<N, N>();
  const Eigen::Matrix<double, M, N> h = hf.template leftCols<N>();
  const Eigen::Matrix<double, N, M> pht = p * h.transpose();
  const Eigen::Matrix<double, M, M> s = h * pht + r;
  const Eigen::Matrix<double, M, M> s_inv = s.inverse();
  UpdateResult out;
  out.nis = y.dot(s_inv * y);
  if (!std::isfinite(out.nis) || (gate > 0 && out.nis > gate)) return out;
  const Eigen::Matrix<double, N, M> k = pht * s_inv;
  x_.template head<N>() += k * y;
  x_(kPsi) = wrap_pi(x_(kPsi));
  const Square ikh = Square::Identity() - k * h;
  // Joseph form: stays symmetric PSD.
  P_.template topLeftCorner<N, N>() = ikh * p * ikh.transpose() + k * r * k.transpose();
  out.accepted = true;
  return out;
}

UpdateResult Ekf::update_position_ne(const Eigen::Vector2d& z, const Eigen::Matrix2d& r,
                                     double gate) {
  Eigen::Matrix<double, 2, kStates> h = Eigen::Matrix<double, 2, kStates>::Zero();
  h(0, kN) = 1;
  h(1, kE) = 1;
  const Eigen::Vector2d y = z - x_.segment<2>(kN);
  return update<2>(y, h, r, gate);
}

UpdateResult Ekf::update_velocity_ne(const Eigen::Vector2d& z, const Eigen::Matrix2d& r,
                                     const Motion& m, double gate) {
  const Eigen::Matrix3d rot = rotation(m.roll, m.pitch, x_(kPsi));
  const Eigen::Vector3d vn = rot * x_.segment<3>(kU);
  Eigen::Matrix<double, 2, kStates> h = Eigen::Matrix<double, 2, kStates>::Zero();
  h.block<2, 3>(0, kU) = rot.topRows<2>();
  h(0, kPsi) = -vn(1);
  h(1, kPsi) = vn(0);
  const Eigen::Vector2d y = z - vn.head<2>();
  return update<2>(y, h, r, gate);
}

UpdateResult Ekf::update_heading(double z, double variance, double gate) {
  Eigen::Matrix<double, 1, kStates> h = Eigen::Matrix<double, 1, kStates>::Zero();
  h(0, kPsi) = 1;
  const Eigen::Matrix<double, 1, 1> y(angle_diff(z, x_(kPsi)));
  return update<1>(y, h, Eigen::Matrix<double, 1, 1>(variance), gate);
}

UpdateResult Ekf::update_depth(double z, double variance, double gate) {
  Eigen::Matrix<double, 1, kStates> h = Eigen::Matrix<double, 1, kStates>::Zero();
  h(0, kD) = 1;
  const Eigen::Matrix<double, 1, 1> y(z - x_(kD));
  return update<1>(y, h, Eigen::Matrix<double, 1, 1>(variance), gate);
}

UpdateResult Ekf::update_vertical_velocity(double z, double variance, double gate) {
  Eigen::Matrix<double, 1, kStates> h = Eigen::Matrix<double, 1, kStates>::Zero();
  h(0, kW) = 1;
  const Eigen::Matrix<double, 1, 1> y(z - x_(kW));
  return update<1>(y, h, Eigen::Matrix<double, 1, 1>(variance), gate);
}

UpdateResult Ekf::update_velocity_body(const Eigen::Vector3d& z, const Eigen::Matrix3d& r,
                                       double gate) {
  Eigen::Matrix<double, 3, kStates> h = Eigen::Matrix<double, 3, kStates>::Zero();
  h(0, kU) = h(1, kV) = h(2, kW) = 1;
  const Eigen::Vector3d y = z - x_.segment<3>(kU);
  return update<3>(y, h, r, gate);
}

double Ekf::sway_std(double std_mps, double rate_gain_s, double r, double u) {
  return std_mps + rate_gain_s * std::abs(r) * std::abs(u);
}

UpdateResult Ekf::update_sway(const Motion& m, double std_mps, double rate_gain_s, double gate) {
  const double sp = std::sin(x_(kPsi)), cp = std::cos(x_(kPsi));
  const double cn = x_(kCurrentN), ce = x_(kCurrentE);
  // h(x) = v - v_c, v_c = -sin(psi) c_n + cos(psi) c_e; z = 0.
  Eigen::Matrix<double, 1, kStates> h = Eigen::Matrix<double, 1, kStates>::Zero();
  h(0, kV) = 1;
  h(0, kPsi) = cp * cn + sp * ce;  // -dv_c/dpsi
  h(0, kCurrentN) = sp;
  h(0, kCurrentE) = -cp;
  const Eigen::Matrix<double, 1, 1> y(-sp * cn + cp * ce - x_(kV));
  const double sd = sway_std(std_mps, rate_gain_s, m.r - x_(kBiasR), x_(kU));
  return update<1>(y, h, Eigen::Matrix<double, 1, 1>(sd * sd), gate);
}

void Ekf::set_block(int index, int n, double variance) {
  P_.middleRows(index, n).setZero();
  P_.middleCols(index, n).setZero();
  for (int i = index; i < index + n; ++i) P_(i, i) = variance;
}

void Ekf::set_position_ne(double n, double e, double variance) {
  x_(kN) = n;
  x_(kE) = e;
  set_block(kN, 2, variance);
}

void Ekf::set_velocity_body(double u, double v, double variance) {
  x_(kU) = u;
  x_(kV) = v;
  set_block(kU, 2, variance);
}

void Ekf::set_heading(double psi, double variance) {
  x_(kPsi) = wrap_pi(psi);
  set_block(kPsi, 1, variance);
}

void Ekf::set_depth(double d, double variance) {
  x_(kD) = d;
  set_block(kD, 1, variance);
}

void Ekf::set_state(int index, double value, double variance) {
  x_(index) = index == kPsi ? wrap_pi(value) : value;
  set_block(index, 1, variance);
}

void Ekf::cap_variance(int index, double cap) {
  if (P_(index, index) > cap) set_block(index, 1, cap);
}

}  // namespace tiller::nav
