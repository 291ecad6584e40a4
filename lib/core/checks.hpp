// Input checks: finite and in-range tests used by every node before a message can act.
// A failed check means the message is dropped and counted (see runtime/node.hpp reject()).
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace tiller {

inline bool finite(double v) {
  return std::isfinite(v);
}

template <std::size_t N>
bool all_finite(const double (&v)[N]) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}
inline bool all_finite(const double* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
inline bool all_finite(const std::vector<double>& v) {
  return all_finite(v.data(), v.size());
}

// Finite and within [lo, hi].
inline bool in_range(double v, double lo, double hi) {
  return std::isfinite(v) && v >= lo && v <= hi;
}
template <std::size_t N>
bool all_in_range(const double (&v)[N], double lo, double hi) {
  for (double x : v)
    if (!in_range(x, lo, hi)) return false;
  return true;
}
inline bool all_in_range(const double* v, std::size_t n, double lo, double hi) {
  for (std::size_t i = 0; i < n; ++i)
    if (!in_range(v[i], lo, hi)) return false;
  return true;
}

}  // namespace tiller
