#include "ahrs/mahony.hpp"

#include <algorithm>
#include <cmath>

namespace tiller::ahrs {

namespace {
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
Vec3 scaled(const Vec3& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
}  // namespace

Quat multiply(const Quat& a, const Quat& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}

Vec3 to_body(const Quat& q, const Vec3& v) {
  // R^T v with R the rotation matrix of q (body -> NED).
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  return {r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
          r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
          r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2]};
}

Vec3 euler_of(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  const double pitch = std::asin(std::clamp(2 * (w * y - z * x), -1.0, 1.0));
  const double yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
  return {roll, pitch, yaw};
}

Quat quat_of_euler(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  return {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
          cr * cp * sy - sr * sp * cy};
}

double angle_between(const Quat& a, const Quat& b) {
  const double d = std::abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
  return 2 * std::acos(std::min(1.0, d));
}

Vec3 Mahony::euler() const {
  return euler_of(q_);
}

bool Mahony::align(const Vec3& accel, const Vec3& mag) {
  const double an = norm(accel), mn = norm(mag);
  if (!(an > 0.5 * p_.gravity) || !(mn > 0)) return false;
  // Body-frame axes of NED: down = -a/|a|; east = down x m; north = east x down.
  const Vec3 d = scaled(accel, -1.0 / an);
  Vec3 e = cross(d, mag);
  const double en = norm(e);
  if (en < 1e-6 * mn) return false;  // field along gravity: no heading
  e = scaled(e, 1.0 / en);
  const Vec3 n = cross(e, d);
  // Rows of R^T are n, e, d in body coordinates: R = [n e d]^T^T; build q from R (body->NED),
  // R[i][j] = component j of NED axis i in the body.
  const double r[3][3] = {{n[0], n[1], n[2]}, {e[0], e[1], e[2]}, {d[0], d[1], d[2]}};
  const double tr = r[0][0] + r[1][1] + r[2][2];
  Quat q;
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    q = {s / 4, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s};
  } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
    const double s = 2 * std::sqrt(1 + r[0][0] - r[1][1] - r[2][2]);
    q = {(r[2][1] - r[1][2]) / s, s / 4, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s};
  } else if (r[1][1] > r[2][2]) {
    const double s = 2 * std::sqrt(1 + r[1][1] - r[0][0] - r[2][2]);
    q = {(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, s / 4, (r[1][2] + r[2][1]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r[2][2] - r[0][0] - r[1][1]);
    q = {(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, s / 4};
  }
  if (q[0] < 0) q = {-q[0], -q[1], -q[2], -q[3]};
  const double qn = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= qn;
  q_ = q;
  aligned_ = true;
  return true;
}

void Mahony::update(const Vec3& gyro, const Vec3& accel, const Vec3* mag, double dt) {
  if (!(dt > 0)) return;
  if (!aligned_ || dt > p_.max_dt) {
    aligned_ = false;
    if (mag != nullptr) align(accel, *mag);
    return;
  }
  Vec3 e{0, 0, 0};
  const double an = norm(accel);
  const Vec3 v_a = to_body(q_, {0, 0, -1});  // predicted direction of the specific force
  if (std::abs(an - p_.gravity) < p_.accel_gate) {
    const Vec3 ea = cross(scaled(accel, 1.0 / an), v_a);
    for (int i = 0; i < 3; ++i) e[i] += ea[i];
  } else {
    ++accel_rejected_;
  }
  if (mag != nullptr) {
    const double mn = norm(*mag);
    const bool ok =
        mn > 0 && (p_.mag_norm <= 0 || std::abs(mn - p_.mag_norm) < p_.mag_gate * p_.mag_norm);
    if (ok) {
      // The field's horizontal part (perpendicular to the estimated down, v_d = -v_a) against the
      // estimated north: the error is along v_d, sin(heading error) at any dip.
      const Vec3 v_d = scaled(v_a, -1.0);
      const Vec3 m = scaled(*mag, 1.0 / mn);
      const double md = dot(m, v_d);
      Vec3 mh{m[0] - md * v_d[0], m[1] - md * v_d[1], m[2] - md * v_d[2]};
      const double mhn = norm(mh);
      if (mhn > 1e-3) {
        mh = scaled(mh, 1.0 / mhn);
        const Vec3 v_n = to_body(q_, {1, 0, 0});
        const Vec3 em = cross(mh, v_n);
        const double along = dot(em, v_d);
        for (int i = 0; i < 3; ++i) e[i] += along * v_d[i];
      }
    } else {
      ++mag_rejected_;
    }
  }
  Vec3 w;
  for (int i = 0; i < 3; ++i) {
    bias_[i] = std::clamp(bias_[i] - p_.ki * e[i] * dt, -p_.max_bias, p_.max_bias);
    w[i] = gyro[i] - bias_[i] + p_.kp * e[i];
  }
  const Quat dq = multiply(q_, {0, w[0], w[1], w[2]});
  Quat q;
  double n2 = 0;
  for (int i = 0; i < 4; ++i) {
    q[i] = q_[i] + 0.5 * dq[i] * dt;
    n2 += q[i] * q[i];
  }
  const double inv = 1.0 / std::sqrt(n2);
  for (int i = 0; i < 4; ++i) q_[i] = q[i] * inv;
}

}  // namespace tiller::ahrs
