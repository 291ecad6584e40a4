#include "sim/vessel_model.hpp"

#include <cmath>
#include <stdexcept>

#include "core/angles.hpp"

namespace tiller::sim {

Matrix3 rotation_zyx(double roll, double pitch, double yaw) {
  const double cf = std::cos(roll), sf = std::sin(roll);
  const double ct = std::cos(pitch), st = std::sin(pitch);
  const double cp = std::cos(yaw), sp = std::sin(yaw);
  Matrix3 r;
  r << cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st,  //
      sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf,   //
      -st, ct * sf, ct * cf;
  return r;
}

VesselModel::VesselModel(const DynamicsParams& params, std::span<const ThrusterGeometry> thrusters)
    : p_(params), surface_(params.kind == ModelKind::kSurface3Dof) {
  if (thrusters.size() > static_cast<std::size_t>(kMaxThrusters))
    throw std::invalid_argument("VesselModel: more than 16 thrusters");
  n_ = static_cast<int>(thrusters.size());
  for (int i = 0; i < n_; ++i) {
    const auto& t = thrusters[static_cast<std::size_t>(i)];
    const double norm = t.direction.norm();
    if (!(norm > 1e-9)) throw std::invalid_argument("VesselModel: thruster direction is zero");
    const Vector3 d = t.direction / norm;
    Vector6 col;
    col << d, t.position.cross(d);
    b_[static_cast<std::size_t>(i)] = col;
  }
  m_inv_ = p_.mass_matrix.inverse();
  constexpr int idx[3] = {0, 1, 5};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      m3_(i, j) = p_.mass_matrix(idx[i], idx[j]);
      c3_(i, j) = p_.coriolis_mass_matrix(idx[i], idx[j]);
    }
  m3_inv_ = m3_.inverse();
}

void VesselModel::reset(const Vector6& eta, const Vector6& nu) {
  eta_ = eta;
  nu_ = nu;
  if (surface_) {
    eta_[2] = eta_[3] = eta_[4] = 0;
    nu_[2] = nu_[3] = nu_[4] = 0;
  }
  thrust_.fill(0.0);
  target_.fill(0.0);
}

void VesselModel::set_thrust_target(int i, double newtons) {
  if (i < 0 || i >= n_) return;
  target_[static_cast<std::size_t>(i)] = std::isfinite(newtons) ? newtons : 0.0;
}

void VesselModel::set_thrust_now(int i, double newtons) {
  if (i < 0 || i >= n_) return;
  set_thrust_target(i, newtons);
  thrust_[static_cast<std::size_t>(i)] = target_[static_cast<std::size_t>(i)];
}

Vector6 VesselModel::thruster_wrench() const {
  Vector6 tau = Vector6::Zero();
  for (int i = 0; i < n_; ++i)
    tau += thrust_[static_cast<std::size_t>(i)] * b_[static_cast<std::size_t>(i)];
  return tau;
}

Vector6 VesselModel::nu_relative(const Vector3& current_ned) const {
  Vector6 nu_r = nu_;
  const Matrix3 r = rotation_zyx(eta_[3], eta_[4], eta_[5]);
  nu_r.head<3>() -= r.transpose() * current_ned;
  if (surface_) nu_r[2] = 0;
  return nu_r;
}

double VesselModel::kinetic_energy(const Vector3& current_ned) const {
  const Vector6 nu_r = nu_relative(current_ned);
  return 0.5 * nu_r.dot(p_.mass_matrix * nu_r);
}

double VesselModel::potential_energy() const {
  if (surface_) return 0.0;
  // U = -(W - B) z - e_z^T R (W r_g - B r_b): the work weight and buoyancy do is -dU.
  const Matrix3 r = rotation_zyx(eta_[3], eta_[4], eta_[5]);
  const Vector3 moment_arm =
      p_.weight_n * p_.center_of_gravity_m - p_.buoyancy_n * p_.center_of_buoyancy_m;
  return -(p_.weight_n - p_.buoyancy_n) * eta_[2] - r.row(2).dot(moment_arm);
}

Vector6 VesselModel::damping(const Vector6& nu_r) const {
  Vector6 f;
  for (int i = 0; i < 6; ++i)
    f[i] = (p_.linear_damping[i] + p_.quadratic_damping[i] * std::abs(nu_r[i])) * nu_r[i];
  if (!surface_ && !p_.damping_center_m.isZero()) {
    // Translational damping at r_d: velocity there, force there, its moment about the origin.
    const Vector3& rd = p_.damping_center_m;
    const Vector3 vd = nu_r.head<3>() + nu_r.tail<3>().cross(rd);
    Vector3 fl;
    for (int i = 0; i < 3; ++i)
      fl[i] = (p_.linear_damping[i] + p_.quadratic_damping[i] * std::abs(vd[i])) * vd[i];
    f.head<3>() = fl;
    f.tail<3>() += rd.cross(fl);
  }
  if (p_.cross_flow.enabled) {
    // Strip theory: each strip at x sees a cross-flow v + x r; drag 0.5 rho T Cd |.|(.) dx.
    const auto& cf = p_.cross_flow;
    const int n = cf.strips;
    const double dx = cf.length_m / n;
    const double k = 0.5 * p_.water_density_kg_m3 * cf.draft_m * cf.cd * dx;
    double y = 0, nn = 0;
    for (int s = 0; s < n; ++s) {
      const double x = -0.5 * cf.length_m + (s + 0.5) * dx;  // strip centre
      const double vx = nu_r[1] + x * nu_r[5];
      const double q = k * std::abs(vx) * vx;
      y += q;
      nn += x * q;
    }
    f[1] += y;
    f[5] += nn;
  }
  return f;
}

Vector6 VesselModel::restoring(const Vector6& eta) const {
  // Fossen 2021 eq. 4.6.
  const double w = p_.weight_n, b = p_.buoyancy_n;
  const Vector3& rg = p_.center_of_gravity_m;
  const Vector3& rb = p_.center_of_buoyancy_m;
  const double sf = std::sin(eta[3]), cf = std::cos(eta[3]);
  const double st = std::sin(eta[4]), ct = std::cos(eta[4]);
  Vector6 g;
  g << (w - b) * st, -(w - b) * ct * sf, -(w - b) * ct * cf,
      -(rg.y() * w - rb.y() * b) * ct * cf + (rg.z() * w - rb.z() * b) * ct * sf,
      (rg.z() * w - rb.z() * b) * st + (rg.x() * w - rb.x() * b) * ct * cf,
      -(rg.x() * w - rb.x() * b) * ct * sf - (rg.y() * w - rb.y() * b) * st;
  return g;
}

Vector6 VesselModel::wind(const Vector6& eta, const Vector6& nu, const Vector3& wind_ned) const {
  Vector6 f = Vector6::Zero();
  if (!surface_ || p_.wind_coefficients.isZero()) return f;
  // VRX usv_wind_plugin: relative wind in the body frame; the yaw term's sign is unchanged
  // from VRX's FLU frame to FRD (both y and the yaw moment flip).
  const double c = std::cos(eta[5]), s = std::sin(eta[5]);
  const double uw = c * wind_ned.x() + s * wind_ned.y() - nu[0];
  const double vw = -s * wind_ned.x() + c * wind_ned.y() - nu[1];
  const Vector3& k = p_.wind_coefficients;
  f[0] = k.x() * uw * std::abs(uw);
  f[1] = k.y() * vw * std::abs(vw);
  f[5] = -2.0 * k.z() * uw * vw;
  return f;
}

void VesselModel::derivative(const Vector6& eta, const Vector6& nu, const Vector6& tau_thr,
                             const Environment& env, Vector6& eta_dot, Vector6& nu_dot) const {
  if (surface_) {
    const double c = std::cos(eta[5]), s = std::sin(eta[5]);
    const double uc = c * env.current_ned.x() + s * env.current_ned.y();
    const double vc = -s * env.current_ned.x() + c * env.current_ned.y();
    const double r = nu[5];
    Vector6 nu_r = Vector6::Zero();
    nu_r[0] = nu[0] - uc;
    nu_r[1] = nu[1] - vc;
    nu_r[5] = r;
    // C(nu_r) nu_r for the 3x3 M (the 6-DOF formula with w = p = q = 0).
    const double ax = c3_(0, 0) * nu_r[0] + c3_(0, 1) * nu_r[1] + c3_(0, 2) * r;
    const double ay = c3_(1, 0) * nu_r[0] + c3_(1, 1) * nu_r[1] + c3_(1, 2) * r;
    const Vector6 d = damping(nu_r);
    const Vector6 w = env.wind ? wind(eta, nu, env.wind_ned) : Vector6::Zero();
    const Eigen::Vector3d rhs(tau_thr[0] + w[0] + ay * r - d[0], tau_thr[1] + w[1] - ax * r - d[1],
                              tau_thr[5] + w[5] - (ay * nu_r[0] - ax * nu_r[1]) - d[5]);
    const Eigen::Vector3d acc = m3_inv_ * rhs;
    nu_dot.setZero();
    nu_dot[0] = acc[0] + r * vc;  // nu_c_dot = -omega x nu_c
    nu_dot[1] = acc[1] - r * uc;
    nu_dot[5] = acc[2];
    eta_dot.setZero();
    eta_dot[0] = c * nu[0] - s * nu[1];
    eta_dot[1] = s * nu[0] + c * nu[1];
    eta_dot[5] = r;
    return;
  }
  const Matrix3 rot = rotation_zyx(eta[3], eta[4], eta[5]);
  const Vector3 v_c = rot.transpose() * env.current_ned;
  const Vector3 omega = nu.tail<3>();
  Vector6 nu_r = nu;
  nu_r.head<3>() -= v_c;
  const Vector3 v1 = nu_r.head<3>();
  const Matrix6& m = p_.coriolis_mass_matrix;
  // Theorem 3.2: C(nu) nu = [-a x nu2; -a x nu1 - b x nu2], a = M11 nu1 + M12 nu2,
  // b = M21 nu1 + M22 nu2.
  const Vector3 a = m.topLeftCorner<3, 3>() * v1 + m.topRightCorner<3, 3>() * omega;
  const Vector3 b = m.bottomLeftCorner<3, 3>() * v1 + m.bottomRightCorner<3, 3>() * omega;
  Vector6 c_nu;
  c_nu << -a.cross(omega), -a.cross(v1) - b.cross(omega);
  Vector6 rhs = tau_thr - c_nu - damping(nu_r) - restoring(eta);
  rhs.head<3>() += rot.transpose() * env.force_ned;
  nu_dot = m_inv_ * rhs;
  nu_dot.head<3>() -= omega.cross(v_c);
  // Kinematics: p_dot = R v, Theta_dot = T(Theta) omega (singular at pitch = +-90 deg).
  eta_dot.head<3>() = rot * nu.head<3>();
  const double sf = std::sin(eta[3]), cf = std::cos(eta[3]);
  // Keep cos(pitch) away from zero so a tumbling vehicle gives large rates, not infinities.
  const double ct_raw = std::cos(eta[4]);
  const double ct = std::abs(ct_raw) < 1e-6 ? std::copysign(1e-6, ct_raw) : ct_raw;
  const double tt = std::sin(eta[4]) / ct;
  eta_dot[3] = omega.x() + sf * tt * omega.y() + cf * tt * omega.z();
  eta_dot[4] = cf * omega.y() - sf * omega.z();
  eta_dot[5] = (sf * omega.y() + cf * omega.z()) / ct;
}

void VesselModel::step(double dt, const Environment& env) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return;
  // Exact lag: T(s) = T_tgt + (T_0 - T_tgt) e^{-s/tau}; one time constant for all thrusters,
  // so the wrench is tau(s) = tau_tgt + (tau_0 - tau_tgt) e^{-s/tau}.
  Vector6 tau0 = Vector6::Zero(), tau_tgt = Vector6::Zero();
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    tau0 += thrust_[k] * b_[k];
    tau_tgt += target_[k] * b_[k];
  }
  const double tc = p_.thruster_time_constant_s;
  const double e_half = tc > 0 ? std::exp(-0.5 * dt / tc) : 0.0;
  const double e_full = e_half * e_half;
  const Vector6 tau_half = tau_tgt + (tau0 - tau_tgt) * e_half;
  const Vector6 tau_end = tau_tgt + (tau0 - tau_tgt) * e_full;

  Vector6 k1e, k1n, k2e, k2n, k3e, k3n, k4e, k4n;
  derivative(eta_, nu_, tau0, env, k1e, k1n);
  derivative(eta_ + 0.5 * dt * k1e, nu_ + 0.5 * dt * k1n, tau_half, env, k2e, k2n);
  derivative(eta_ + 0.5 * dt * k2e, nu_ + 0.5 * dt * k2n, tau_half, env, k3e, k3n);
  derivative(eta_ + dt * k3e, nu_ + dt * k3n, tau_end, env, k4e, k4n);
  eta_ += (dt / 6.0) * (k1e + 2.0 * k2e + 2.0 * k3e + k4e);
  nu_ += (dt / 6.0) * (k1n + 2.0 * k2n + 2.0 * k3n + k4n);
  eta_[3] = wrap_pi(eta_[3]);
  eta_[5] = wrap_pi(eta_[5]);
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    thrust_[k] = target_[k] + (thrust_[k] - target_[k]) * e_full;
  }
}

}  // namespace tiller::sim
