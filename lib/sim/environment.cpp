#include "sim/environment.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/angles.hpp"

namespace tiller::sim {

CurrentModel::CurrentModel(const CurrentParams& p, std::uint64_t seed) : p_(p), rng_(seed) {
  const bool ok = std::isfinite(p.speed_m_s) && p.speed_m_s >= 0 && std::isfinite(p.toward_rad) &&
                  std::isfinite(p.speed_max_m_s) && p.speed_max_m_s >= 0 &&
                  std::isfinite(p.mu_per_s) && p.mu_per_s >= 0 && std::isfinite(p.speed_std_m_s) &&
                  p.speed_std_m_s >= 0 && std::isfinite(p.direction_std_rad) &&
                  p.direction_std_rad >= 0;
  if (!ok) {
    throw std::invalid_argument(
        "CurrentModel: speeds, saturation, rate and deviations must be finite and >= 0");
  }
}

void CurrentModel::step(double dt) {
  if (p_.model != CurrentParams::Model::kGaussMarkov || !(dt > 0)) return;
  // Exact discretisation of x_dot = -mu x + w with stationary standard deviation s:
  // x+ = a x + s sqrt(1 - a^2) n, a = exp(-mu dt).
  const double a = std::exp(-p_.mu_per_s * dt);
  const double k = std::sqrt(std::max(0.0, 1.0 - a * a));
  speed_dev_ = a * speed_dev_ + p_.speed_std_m_s * k * normal_(rng_);
  dir_dev_ = a * dir_dev_ + p_.direction_std_rad * k * normal_(rng_);
}

double CurrentModel::speed() const {
  if (p_.model == CurrentParams::Model::kNone) return 0.0;
  return std::clamp(p_.speed_m_s + speed_dev_, 0.0, p_.speed_max_m_s);
}

double CurrentModel::toward() const {
  return wrap_pi(p_.toward_rad + dir_dev_);
}

Vector3 CurrentModel::velocity_ned() const {
  const double s = speed();
  const double d = toward();
  return {s * std::cos(d), s * std::sin(d), 0.0};
}

Vector3 WindParams::velocity_ned() const {
  return {-speed_m_s * std::cos(from_rad), -speed_m_s * std::sin(from_rad), 0.0};
}

OdometryNoise::OdometryNoise(const OdometryNoiseParams& p, std::uint64_t seed)
    : p_(p), rng_(seed) {}

void OdometryNoise::apply(Vector6& eta, Vector6& nu) {
  if (!p_.any()) return;
  for (int i = 0; i < 3; ++i) eta[i] += p_.position_std_m * normal_(rng_);
  for (int i = 3; i < 6; ++i) eta[i] = wrap_pi(eta[i] + p_.orientation_std_rad * normal_(rng_));
  for (int i = 0; i < 3; ++i) nu[i] += p_.linear_velocity_std_m_s * normal_(rng_);
  for (int i = 3; i < 6; ++i) nu[i] += p_.angular_velocity_std_rad_s * normal_(rng_);
}

}  // namespace tiller::sim
