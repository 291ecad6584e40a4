// An attitude and heading reference (AHRS) from raw gyro, accelerometer and magnetometer: the
// explicit complementary filter of Mahony, Hamel and Pflimlin ("Nonlinear Complementary Filters
// on the Special Orthogonal Group", IEEE Trans. Automatic Control 53(5), 2008,
// doi:10.1109/TAC.2008.923738), in the quaternion form Madgwick's report uses
// (S. Madgwick, "An efficient orientation filter for inertial and inertial/magnetic sensor
// arrays", 2010). Debian has no AHRS library (apt-cache search madgwick / imu filter: none).
//
// Frames: body FRD (x forward, y right, z down), earth NED with x along MAGNETIC north (the
// caller adds the declination). q = [w x y z] rotates body to NED, as imu_t.orientation.
// Inputs: angular rate (rad/s, body), specific force (m/s^2, body; level at rest [0 0 -g]),
// magnetic field (any unit, body, hard/soft-iron corrected: ahrs/compass_calibration.hpp).
// Each update, with v_a = R^T [0 0 -1] the predicted direction of the specific force:
//   e_a = a/|a| x v_a                               (roll and pitch from gravity)
//   e_m = ((m_h x v_n) . v_d) v_d                  (heading only: the magnetometer never tilts)
//   b  += -ki (e_a + e_m) dt                        (gyro bias, clamped to max_bias)
//   w'  = w - b + kp (e_a + e_m);  q += 1/2 q (0, w') dt, normalised
// with v_d = -v_a the estimated down, m_h the unit horizontal part of the field (perpendicular
// to v_d) and v_n = R^T [1 0 0] the estimated north, so the heading gain is kp at any dip. The
// accelerometer is used only when | |a| - g | < accel_gate (not while accelerating hard); the
// magnetometer only when its norm is within mag_gate of the calibrated field.
// The first update with both vectors sets q directly (TRIAD: down from the accelerometer, north
// from the horizontal field), so there is no slow start. Deterministic: the state depends only
// on the samples and the dt given; no allocation.
#pragma once

#include <array>

namespace tiller::ahrs {

struct MahonyParams {
  double kp = 1.0;           // 1/s: proportional gain (bandwidth of the correction)
  double ki = 0.1;           // 1/s^2: bias integral gain (slow pole ki/kp: ~9 s)
  double max_bias = 0.1;     // rad/s per axis
  double gravity = 9.80665;  // m/s^2
  double accel_gate = 2.0;   // m/s^2
  double mag_norm = 0;       // expected |m| (0: not gated)
  double mag_gate = 0.25;    // fraction of mag_norm
  double max_dt = 0.1;       // s: a longer gap re-aligns from the next vectors
};

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // w x y z

class Mahony {
 public:
  explicit Mahony(const MahonyParams& p = {}) : p_(p) {}
  // One sample. mag may be null (no new field this step). dt in s (> 0).
  void update(const Vec3& gyro, const Vec3& accel, const Vec3* mag, double dt);
  // Sets q from one accelerometer and magnetometer pair (TRIAD). False if either is degenerate.
  bool align(const Vec3& accel, const Vec3& mag);
  void reset() {
    aligned_ = false;
    bias_ = {0, 0, 0};
  }

  bool aligned() const { return aligned_; }
  const Quat& q() const { return q_; }
  const Vec3& gyro_bias() const { return bias_; }
  // Roll, pitch, yaw (rad, ZYX Euler of q; yaw clockwise from magnetic north in (-pi, pi]).
  Vec3 euler() const;
  // Samples where the accelerometer / magnetometer were left out by their gates.
  long accel_rejected() const { return accel_rejected_; }
  long mag_rejected() const { return mag_rejected_; }

 private:
  MahonyParams p_;
  Quat q_{1, 0, 0, 0};
  Vec3 bias_{0, 0, 0};
  bool aligned_ = false;
  long accel_rejected_ = 0, mag_rejected_ = 0;
};

// Helpers shared with the tests: ZYX Euler of a body->NED quaternion, its inverse, Hamilton
// product, and v_body = R(q)^T v_ned.
Vec3 euler_of(const Quat& q);
Quat quat_of_euler(double roll, double pitch, double yaw);
Quat multiply(const Quat& a, const Quat& b);
Vec3 to_body(const Quat& q, const Vec3& v_ned);
// The smallest rotation angle between two attitudes (rad, [0, pi]).
double angle_between(const Quat& a, const Quat& b);

}  // namespace tiller::ahrs
