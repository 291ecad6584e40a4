// The AHRS (ahrs/mahony.hpp) against a simulated rotation with known truth, and the compass
// calibration's ellipsoid fit (ahrs/compass_calibration.hpp) against a known hard/soft iron.
//
// The rotation: roll 20 deg sin(0.5 t), pitch 15 deg sin(0.3 t + 0.5), yaw 0.2 rad/s (turning
// circles), sampled at 100 Hz for 120 s; the gyro has a bias of (0.01, -0.02, 0.015) rad/s
// and 0.002 rad/s of white noise, the accelerometer 0.05 m/s^2, the magnetometer 0.3 uT on a
// field of (20, 0, 45) uT NED (dip 66 deg); the noise is seeded (std::mt19937, seed 33).
// Figures (printed): RMS attitude error over 30..120 s, RMS tilt and heading errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "ahrs/compass_calibration.hpp"
#include "ahrs/mahony.hpp"

namespace {
using namespace tiller::ahrs;
constexpr double kDeg = std::numbers::pi / 180.0;

struct Truth {
  double roll, pitch, yaw;
  Vec3 omega;  // body rates, rad/s
};

Truth truth_at(double t) {
  const double a = 20 * kDeg, b = 15 * kDeg;
  Truth s;
  s.roll = a * std::sin(0.5 * t);
  s.pitch = b * std::sin(0.3 * t + 0.5);
  s.yaw = std::remainder(0.2 * t, 2 * std::numbers::pi);
  const double dr = a * 0.5 * std::cos(0.5 * t), dp = b * 0.3 * std::cos(0.3 * t + 0.5), dy = 0.2;
  // ZYX Euler rates -> body rates.
  s.omega = {dr - dy * std::sin(s.pitch),
             dp * std::cos(s.roll) + dy * std::cos(s.pitch) * std::sin(s.roll),
             -dp * std::sin(s.roll) + dy * std::cos(s.pitch) * std::cos(s.roll)};
  return s;
}

struct Figures {
  double rms_attitude_deg = 0, max_attitude_deg = 0, rms_tilt_deg = 0, rms_heading_deg = 0;
  Quat final_q{};
  Vec3 bias{};
};

double wrap(double a) {
  return std::remainder(a, 2 * std::numbers::pi);
}

// Runs the filter over the simulated rotation. disturb: the field doubles for 5 s at t = 60 s (a
// magnet near the compass).
Figures run(const MahonyParams& p, bool disturb = false) {
  std::mt19937 rng(33);
  std::normal_distribution<double> g_noise(0, 0.002), a_noise(0, 0.05), m_noise(0, 0.3);
  const Vec3 bias{0.01, -0.02, 0.015};
  const Vec3 field{20, 0, 45};
  Mahony f(p);
  const double dt = 0.01;
  double sa = 0, st = 0, sh = 0, mx = 0;
  int n = 0;
  for (int k = 0; k <= 12000; ++k) {
    const double t = k * dt;
    const Truth s = truth_at(t);
    const Quat q = quat_of_euler(s.roll, s.pitch, s.yaw);
    Vec3 gyro, acc, mag;
    const Vec3 a0 = to_body(q, {0, 0, -p.gravity});
    const double gain = disturb && t >= 60 && t < 65 ? 2.0 : 1.0;
    const Vec3 m0 = to_body(q, {gain * field[0], gain * field[1], gain * field[2]});
    for (int i = 0; i < 3; ++i) {
      gyro[i] = s.omega[i] + bias[i] + g_noise(rng);
      acc[i] = a0[i] + a_noise(rng);
      mag[i] = m0[i] + m_noise(rng);
    }
    f.update(gyro, acc, &mag, dt);
    if (t < 30) continue;
    const double e = angle_between(f.q(), q) / kDeg;
    const Vec3 eu = f.euler();
    const double tilt = std::hypot(wrap(eu[0] - s.roll), wrap(eu[1] - s.pitch)) / kDeg;
    const double head = wrap(eu[2] - s.yaw) / kDeg;
    sa += e * e;
    st += tilt * tilt;
    sh += head * head;
    mx = std::max(mx, e);
    ++n;
  }
  Figures r;
  r.rms_attitude_deg = std::sqrt(sa / n);
  r.max_attitude_deg = mx;
  r.rms_tilt_deg = std::sqrt(st / n);
  r.rms_heading_deg = std::sqrt(sh / n);
  r.final_q = f.q();
  r.bias = f.gyro_bias();
  return r;
}

TEST(Mahony, AlignsFromOneAccelerometerAndMagnetometerPair) {
  for (const double yaw : {0.0, 90.0, -135.0, 179.0}) {
    const Quat q = quat_of_euler(10 * kDeg, -25 * kDeg, yaw * kDeg);
    Mahony f;
    ASSERT_TRUE(f.align(to_body(q, {0, 0, -9.80665}), to_body(q, {20, 0, 45})));
    EXPECT_LT(angle_between(f.q(), q), 1e-9) << "yaw " << yaw;
    const Vec3 e = f.euler();
    EXPECT_NEAR(e[0], 10 * kDeg, 1e-9);
    EXPECT_NEAR(e[1], -25 * kDeg, 1e-9);
    EXPECT_NEAR(wrap(e[2] - yaw * kDeg), 0, 1e-9);
  }
  Mahony f;
  EXPECT_FALSE(f.align({0, 0, -9.8}, {0, 0, 40}));  // field along gravity: no heading
  EXPECT_FALSE(f.align({0, 0, 0}, {20, 0, 45}));    // free fall
  EXPECT_FALSE(f.aligned());
}

TEST(Mahony, TracksASimulatedRotationWithKnownTruth) {
  const Figures r = run(MahonyParams{});
  std::printf(
      "AHRS over 30..120 s of the rotation: attitude RMS %.3f deg (max %.3f), tilt RMS %.3f deg, "
      "heading RMS %.3f deg; gyro bias estimate %.4f %.4f %.4f rad/s (truth 0.01 -0.02 0.015)\n",
      r.rms_attitude_deg, r.max_attitude_deg, r.rms_tilt_deg, r.rms_heading_deg, r.bias[0],
      r.bias[1], r.bias[2]);
  EXPECT_LT(r.rms_attitude_deg, 0.5);
  EXPECT_LT(r.max_attitude_deg, 1.5);
  EXPECT_LT(r.rms_tilt_deg, 0.5);
  EXPECT_LT(r.rms_heading_deg, 0.5);
  EXPECT_NEAR(r.bias[0], 0.01, 0.003);
  EXPECT_NEAR(r.bias[1], -0.02, 0.003);
  EXPECT_NEAR(r.bias[2], 0.015, 0.003);
  // Without the gyro-bias integral the bias shows as a standing error (bias / kp, ~1.5 deg).
  MahonyParams no_i;
  no_i.ki = 0;
  const Figures p = run(no_i);
  std::printf("without the bias integral: attitude RMS %.3f deg\n", p.rms_attitude_deg);
  EXPECT_GT(p.rms_attitude_deg, 3 * r.rms_attitude_deg);
}

TEST(Mahony, IsDeterministic) {
  const Figures a = run(MahonyParams{}), b = run(MahonyParams{});
  for (int i = 0; i < 4; ++i) EXPECT_EQ(a.final_q[i], b.final_q[i]);
}

TEST(Mahony, MagnetometerGateKeepsAMagnetOut) {
  MahonyParams gated;
  gated.mag_norm = std::hypot(20.0, 45.0);
  const Figures g = run(gated, true);
  MahonyParams open;
  const Figures o = run(open, true);
  std::printf("field doubled for 5 s: heading RMS %.3f deg gated, %.3f deg not gated\n",
              g.rms_heading_deg, o.rms_heading_deg);
  EXPECT_LT(g.rms_heading_deg, 0.5);
  // A doubled field along the same direction does not turn the heading either; what the gate
  // must not do is reject the good samples around it.
  EXPECT_LT(o.rms_heading_deg, 0.5);
}

TEST(Mahony, NeverTiltsFromTheMagnetometer) {
  // Level and still, the magnetometer 30 deg off: only yaw moves.
  Mahony f;
  ASSERT_TRUE(f.align({0, 0, -9.80665}, {20, 0, 45}));
  const Quat turned = quat_of_euler(0, 0, 30 * kDeg);
  const Vec3 m = to_body(turned, {20, 0, 45});
  for (int k = 0; k < 6000; ++k) f.update({0, 0, 0}, {0, 0, -9.80665}, &m, 0.01);
  const Vec3 e = f.euler();
  EXPECT_NEAR(e[0], 0, 1e-6);
  EXPECT_NEAR(e[1], 0, 1e-6);
  EXPECT_NEAR(e[2], 30 * kDeg, 0.2 * kDeg);
}

// Compass calibration --------------------------------------------------------------------------

// Raw samples of a true field of 50 uT turned through `n` attitudes (directions on a Fibonacci
// sphere, or only around z when yaw_only), seen through soft iron sinv and hard iron o.
std::vector<std::array<double, 3>> recorded(const std::array<double, 9>& sinv,
                                            const std::array<double, 3>& o, int n, bool yaw_only) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.1);
  std::vector<std::array<double, 3>> out;
  for (int k = 0; k < n; ++k) {
    double b[3];
    if (yaw_only) {
      const double a = 2 * std::numbers::pi * k / n;
      b[0] = 20 * std::cos(a);
      b[1] = 20 * std::sin(a);
      b[2] = 45.8;
    } else {
      const double z = 1 - 2 * (k + 0.5) / n, r = std::sqrt(1 - z * z);
      const double a = k * std::numbers::pi * (3 - std::sqrt(5.0));
      b[0] = 50 * r * std::cos(a);
      b[1] = 50 * r * std::sin(a);
      b[2] = 50 * z;
    }
    std::array<double, 3> raw;
    for (int i = 0; i < 3; ++i)
      raw[i] =
          sinv[3 * i] * b[0] + sinv[3 * i + 1] * b[1] + sinv[3 * i + 2] * b[2] + o[i] + noise(rng);
    out.push_back(raw);
  }
  return out;
}

TEST(CompassCalibration, RecoversHardAndSoftIron) {
  // Hard iron (12, -30, 5) uT; soft iron: gains 1.2, 0.85, 1.0 with cross-coupling.
  const std::array<double, 9> sinv = {1.2, 0.05, -0.03, 0.05, 0.85, 0.04, -0.03, 0.04, 1.0};
  const std::array<double, 3> o = {12, -30, 5};
  const auto raw = recorded(sinv, o, 400, false);
  const FitResult r = fit_ellipsoid(raw);
  ASSERT_TRUE(r.ok) << r.why;
  std::printf(
      "compass fit: offset %.3f %.3f %.3f uT, radius %.3f uT, residual %.5f, coverage %.3f\n",
      r.cal.offset[0], r.cal.offset[1], r.cal.offset[2], r.radius, r.relative_residual, r.coverage);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r.cal.offset[i], o[i], 0.05);
  EXPECT_LT(r.relative_residual, 0.005);  // the 0.1 uT noise on 50 uT is 0.002
  EXPECT_GT(r.coverage, 0.9);
  // S is (radius / 50) * sinv^-1: S * sinv = (radius / 50) I.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = 0;
      for (int k = 0; k < 3; ++k) v += r.cal.matrix[3 * i + k] * sinv[3 * k + j];
      EXPECT_NEAR(v, i == j ? r.radius / 50.0 : 0.0, 0.005) << i << "," << j;
    }
  }
  // Uncorrected, the norm varies by tens of percent; corrected, by the noise.
  double lo = 1e9, hi = 0;
  for (const auto& s : raw) {
    const auto b = r.cal.apply(s);
    const double n = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    lo = std::min(lo, n);
    hi = std::max(hi, n);
  }
  EXPECT_LT((hi - lo) / r.radius, 0.02);
}

TEST(CompassCalibration, RefusesAYawOnlyRotationAndTooFewSamples) {
  const std::array<double, 9> eye = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const FitResult flat = fit_ellipsoid(recorded(eye, {0, 0, 0}, 400, true));
  EXPECT_FALSE(flat.ok);
  EXPECT_NE(flat.why.find("attitudes"), std::string::npos) << flat.why;
  const FitResult few = fit_ellipsoid(recorded(eye, {0, 0, 0}, 20, false));
  EXPECT_FALSE(few.ok);
  EXPECT_NE(few.why.find("20 samples"), std::string::npos) << few.why;
}

}  // namespace
