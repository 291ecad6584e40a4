// Disturbances for the simulator: water current (constant or seeded Gauss-Markov), wind, and
// seeded odometry noise. Velocities in NED, m/s; directions are NED headings in radians
// (0 = north, + clockwise). Same seed, same sequence, bit for bit; no clock, no heap per step.
#pragma once

#include <cstdint>
#include <random>

#include "sim/dynamics.hpp"

namespace tiller::sim {

struct CurrentParams {
  enum class Model { kNone, kConstant, kGaussMarkov };
  Model model = Model::kNone;
  double speed_m_s = 0;   // mean speed
  double toward_rad = 0;  // mean direction the water flows towards
  // Gauss-Markov (Fossen eq. 8.22, x_dot + mu x = w): the speed and the direction each get a
  // first-order Gauss-Markov deviation with rate mu (1/s) and the given stationary standard
  // deviation, integrated exactly; the speed is then saturated to [0, speed_max_m_s].
  double mu_per_s = 0.01;
  double speed_std_m_s = 0;
  double direction_std_rad = 0;
  double speed_max_m_s = 5.0;
};

class CurrentModel {
 public:
  // Throws std::invalid_argument for a negative or non-finite speed, saturation, rate or
  // deviation (speed() clamps to [0, speed_max_m_s], which needs speed_max_m_s >= 0).
  CurrentModel(const CurrentParams& p, std::uint64_t seed);
  // Advances the Gauss-Markov processes by dt seconds (no-op for none/constant).
  void step(double dt);
  Vector3 velocity_ned() const;
  double speed() const;
  double toward() const;

 private:
  CurrentParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  double speed_dev_ = 0, dir_dev_ = 0;
};

// Wind over a surface vessel: constant speed from a direction (meteorological: where it
// blows FROM, NED heading).
struct WindParams {
  double speed_m_s = 0;
  double from_rad = 0;
  Vector3 velocity_ned() const;  // the air's velocity
};

// Standard deviations of the noise added to published odometry (0 = none).
struct OdometryNoiseParams {
  double position_std_m = 0;
  double orientation_std_rad = 0;         // roll, pitch, yaw
  double linear_velocity_std_m_s = 0;     // u v w
  double angular_velocity_std_rad_s = 0;  // p q r
  bool any() const {
    return position_std_m > 0 || orientation_std_rad > 0 || linear_velocity_std_m_s > 0 ||
           angular_velocity_std_rad_s > 0;
  }
};

class OdometryNoise {
 public:
  OdometryNoise(const OdometryNoiseParams& p, std::uint64_t seed);
  // Adds noise in place (eta: position and orientation; nu: body velocity). Yaw stays wrapped.
  void apply(Vector6& eta, Vector6& nu);

 private:
  OdometryNoiseParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace tiller::sim
