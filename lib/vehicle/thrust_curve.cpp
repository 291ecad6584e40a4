#include "vehicle/thrust_curve.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "vehicle/t200_tables.hpp"

namespace tiller {
namespace {

constexpr double kKgf = 9.80665;

[[noreturn]] void bad(const std::string& what) {
  throw std::invalid_argument(what);
}

std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

ThrustCurve ThrustCurve::linear(double forward_n, double reverse_n) {
  if (!(forward_n > 0) || !(reverse_n > 0) || !std::isfinite(forward_n) ||
      !std::isfinite(reverse_n))
    bad("linear curve: forward_n and reverse_n must be positive finite numbers");
  ThrustCurve c(Kind::kLinear);
  c.fwd_ = forward_n;
  c.rev_ = reverse_n;
  c.t_max_ = forward_n;
  c.t_min_ = -reverse_n;
  c.description_ = "linear(" + num(forward_n) + ", " + num(reverse_n) + ")";
  return c;
}

ThrustCurve ThrustCurve::quadratic(double forward_n, double reverse_n) {
  ThrustCurve c = linear(forward_n, reverse_n);
  c.kind_ = Kind::kQuadratic;
  c.description_ = "quadratic(" + num(forward_n) + ", " + num(reverse_n) + ")";
  return c;
}

ThrustCurve ThrustCurve::table(std::vector<double> command, std::vector<double> thrust_n) {
  if (command.size() != thrust_n.size() || command.size() < 3)
    bad("table curve: command and thrust_n need the same length, at least 3 points");
  for (std::size_t i = 0; i < command.size(); ++i)
    if (!std::isfinite(command[i]) || !std::isfinite(thrust_n[i]))
      bad("table curve: every point must be finite");
  if (command.front() != -1.0 || command.back() != 1.0)
    bad("table curve: command must run from -1 to 1");
  for (std::size_t i = 1; i < command.size(); ++i) {
    if (!(command[i] > command[i - 1])) bad("table curve: command must be strictly increasing");
    if (thrust_n[i] < thrust_n[i - 1])
      bad("table curve: thrust_n must not decrease (at command " + num(command[i]) + ")");
    if (thrust_n[i] == thrust_n[i - 1] && thrust_n[i] != 0.0)
      bad("table curve: a flat part is allowed only at zero thrust (the dead band)");
  }
  if (!(thrust_n.front() < 0) || !(thrust_n.back() > 0))
    bad("table curve: thrust must be negative at -1 and positive at 1");
  ThrustCurve c(Kind::kTable);
  c.u_ = std::move(command);
  c.t_ = std::move(thrust_n);
  if (std::abs(c.thrust(0.0)) > 1e-9) bad("table curve: thrust at command 0 must be 0");
  c.t_min_ = c.t_.front();
  c.t_max_ = c.t_.back();
  c.du_dt_.resize(c.u_.size() - 1);
  for (std::size_t i = 0; i + 1 < c.u_.size(); ++i)
    c.du_dt_[i] = c.t_[i + 1] > c.t_[i] ? (c.u_[i + 1] - c.u_[i]) / (c.t_[i + 1] - c.t_[i]) : 0.0;
  c.description_ = "table(" + std::to_string(c.u_.size()) + " points)";
  return c;
}

ThrustCurve ThrustCurve::voltage_table(std::vector<double> command, std::vector<double> thrust_lo,
                                       double v_lo, std::vector<double> thrust_hi, double v_hi) {
  if (!(v_lo > 0) || !(v_hi > v_lo) || !std::isfinite(v_hi))
    bad("voltage table: expected 0 < v_lo < v_hi volts");
  table(command, thrust_lo);  // each validated as a table on its own
  ThrustCurve c = table(command, thrust_hi);
  c.t_lo_ = std::move(thrust_lo);
  c.t_hi_ = std::move(thrust_hi);
  c.v_lo_ = v_lo;
  c.v_hi_ = v_hi;
  c.volts_ = v_hi;
  c.description_ = "voltage table(" + std::to_string(c.u_.size()) + " points, " + num(v_lo) + ".." +
                   num(v_hi) + " V)";
  return c;
}

void ThrustCurve::set_supply_voltage(double volts) {
  if (t_lo_.empty() || !std::isfinite(volts)) return;
  volts_ = std::clamp(volts, v_lo_, v_hi_);
  const double w = (volts_ - v_lo_) / (v_hi_ - v_lo_);
  for (std::size_t k = 0; k < t_.size(); ++k) t_[k] = (1 - w) * t_lo_[k] + w * t_hi_[k];
  for (std::size_t i = 0; i + 1 < u_.size(); ++i)
    du_dt_[i] = t_[i + 1] > t_[i] ? (u_[i + 1] - u_[i]) / (t_[i + 1] - t_[i]) : 0.0;
  t_min_ = t_.front();
  t_max_ = t_.back();
}

ThrustCurve ThrustCurve::polynomial(std::vector<double> coefficients) {
  if (coefficients.size() < 2) bad("polynomial curve: at least coefficients c0 and c1");
  for (double v : coefficients)
    if (!std::isfinite(v)) bad("polynomial curve: coefficients must be finite");
  if (coefficients[0] != 0.0) bad("polynomial curve: c0 must be 0 (no thrust at command 0)");
  ThrustCurve c(Kind::kPolynomial);
  c.c_ = std::move(coefficients);
  if (!(c.poly_deriv(0.0) > 0)) bad("polynomial curve: thrust must increase at command 0");
  // Usable range: from 0 outwards while the curve keeps increasing.
  auto edge = [&](double sign) {
    const int steps = 2048;
    double prev = 0;
    for (int k = 1; k <= steps; ++k) {
      const double u = sign * k / static_cast<double>(steps);
      if (!(c.poly_deriv(u) > 0)) {
        double lo = prev, hi = u;  // derivative > 0 at lo, <= 0 at hi
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (c.poly_deriv(mid) > 0 ? lo : hi) = mid;
        }
        return lo;
      }
      prev = u;
    }
    return sign;
  };
  c.u_max_ = edge(1.0);
  c.u_min_ = edge(-1.0);
  c.t_max_ = c.poly(c.u_max_);
  c.t_min_ = c.poly(c.u_min_);
  if (!(c.t_max_ > 0) || !(c.t_min_ < 0)) bad("polynomial curve: no usable thrust range");
  c.finish_monotone_table();
  std::ostringstream os;
  os << "polynomial(degree " << c.c_.size() - 1 << ", usable command " << c.u_min_ << ".."
     << c.u_max_ << ")";
  c.description_ = os.str();
  return c;
}

void ThrustCurve::finish_monotone_table() {
  const int n = 1025;
  u_.resize(n);
  t_.resize(n);
  for (int k = 0; k < n; ++k) {
    u_[static_cast<std::size_t>(k)] = u_min_ + (u_max_ - u_min_) * k / (n - 1.0);
    t_[static_cast<std::size_t>(k)] = poly(u_[static_cast<std::size_t>(k)]);
  }
}

ThrustCurve ThrustCurve::preset(std::string_view name) {
  if (name == "t200_12v") {
    // us:      1100   1200   1300   1400   1464 1536  1600  1700  1800  1900
    // kgf:    -2.90  -1.95  -1.02  -0.32   0    0     0.39  1.28  2.46  3.71
    std::vector<double> us = {1100, 1200, 1300, 1400, 1464, 1536, 1600, 1700, 1800, 1900};
    std::vector<double> kgf = {-2.90, -1.95, -1.02, -0.32, 0, 0, 0.39, 1.28, 2.46, 3.71};
    std::vector<double> u, t;
    for (std::size_t i = 0; i < us.size(); ++i) {
      u.push_back((us[i] - 1500.0) / 400.0);
      t.push_back(kgf[i] * kKgf);
    }
    ThrustCurve c = table(u, t);
    c.description_ = "t200_12v";
    return c;
  }
  if (name == "t200" || name == "t200_16v" || name == "t200_14v8") {
    std::vector<double> u, lo, hi;
    for (std::size_t i = 0; i < t200::kPulseUs.size(); ++i) {
      u.push_back((t200::kPulseUs[i] - 1500.0) / 400.0);
      lo.push_back(t200::kKgf12V[i] * kKgf);
      hi.push_back(t200::kKgf16V[i] * kKgf);
    }
    ThrustCurve c = voltage_table(u, lo, 12.0, hi, 16.0);
    c.description_ = std::string(name);
    if (name == "t200") return c;
    c.set_supply_voltage(name == "t200_16v" ? 16.0 : 14.8);
    c.t_lo_.clear();  // fixed at that voltage
    c.t_hi_.clear();
    return c;
  }
  if (name == "t200_poly") {
    ThrustCurve c = polynomial({0, 8.9, 0, 176.0, 0, -404.1, 0, 389.9, 0, -140.3});
    c.description_ = "t200_poly";
    return c;
  }
  bad("unknown thrust curve preset '" + std::string(name) +
      "' (known: t200_12v, t200_14v8, t200_16v, t200, t200_poly)");
}

std::vector<std::string> ThrustCurve::preset_names() {
  return {"t200_12v", "t200_14v8", "t200_16v", "t200", "t200_poly"};
}

double ThrustCurve::poly(double u) const {
  double acc = 0;
  for (std::size_t k = c_.size(); k-- > 0;) acc = acc * u + c_[k];
  return acc;
}

double ThrustCurve::poly_deriv(double u) const {
  double acc = 0;
  for (std::size_t k = c_.size(); k-- > 1;) acc = acc * u + static_cast<double>(k) * c_[k];
  return acc;
}

double ThrustCurve::thrust(double u) const {
  if (!(u == u)) return 0.0;  // NaN -> no thrust
  u = std::clamp(u, u_min_, u_max_);
  switch (kind_) {
    case Kind::kLinear:
      return u >= 0 ? fwd_ * u : rev_ * u;
    case Kind::kQuadratic:
      return u >= 0 ? fwd_ * u * u : -rev_ * u * u;
    case Kind::kPolynomial:
      return poly(u);
    case Kind::kTable: {
      std::size_t k = 0;
      while (k + 2 < u_.size() && u > u_[k + 1]) ++k;
      const double s = (u - u_[k]) / (u_[k + 1] - u_[k]);
      return t_[k] + s * (t_[k + 1] - t_[k]);
    }
  }
  return 0.0;
}

double ThrustCurve::command(double f) const {
  if (!(f == f) || f == 0.0) return 0.0;
  if (f >= t_max_) return u_max_;
  if (f <= t_min_) return u_min_;
  switch (kind_) {
    case Kind::kLinear:
      return f >= 0 ? f / fwd_ : f / rev_;
    case Kind::kQuadratic:
      return f >= 0 ? std::sqrt(f / fwd_) : -std::sqrt(-f / rev_);
    case Kind::kTable: {
      // f > 0: first point with t >= f closes the segment (t_k < f <= t_k+1, never flat since
      // flat parts are at 0); f < 0: first point with t > f (t_k <= f < t_k+1).
      const auto it = f > 0 ? std::lower_bound(t_.begin(), t_.end(), f)
                            : std::upper_bound(t_.begin(), t_.end(), f);
      const auto k = static_cast<std::size_t>(it - t_.begin()) - 1;
      return u_[k] + (f - t_[k]) * du_dt_[k];
    }
    case Kind::kPolynomial: {
      // Bisection on the monotone samples, linear guess, then Newton kept inside the bracket.
      std::size_t lo = 0, hi = t_.size() - 1;
      while (hi - lo > 1) {
        const std::size_t mid = (lo + hi) / 2;
        (t_[mid] <= f ? lo : hi) = mid;
      }
      double u = u_[lo] + (f - t_[lo]) / (t_[hi] - t_[lo]) * (u_[hi] - u_[lo]);
      for (int it = 0; it < 2; ++it) {
        const double d = poly_deriv(u);
        if (!(d > 0)) break;
        u = std::clamp(u - (poly(u) - f) / d, u_[lo], u_[hi]);
      }
      return u;
    }
  }
  return 0.0;
}

}  // namespace tiller
