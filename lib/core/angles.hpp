// Angle helpers. Radians everywhere; headings are NED (0 = north, + clockwise seen from above),
// wrapped to (-pi, pi].
#pragma once

#include <cmath>

namespace tiller {

constexpr double kPi = 3.14159265358979323846;

constexpr double deg_to_rad(double d) {
  return d * kPi / 180.0;
}
constexpr double rad_to_deg(double r) {
  return r * 180.0 / kPi;
}

// Wraps an angle to (-pi, pi].
inline double wrap_pi(double a) {
  if (!std::isfinite(a)) return a;
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

// Smallest signed difference a - b, in (-pi, pi].
inline double angle_diff(double a, double b) {
  return wrap_pi(a - b);
}

}  // namespace tiller
