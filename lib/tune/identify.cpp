#include "tune/identify.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "tune/text_edit.hpp"

namespace tiller::tune {

namespace {

// Per motion sample k: the integral of the filtered wrench from the first sample (6 components).
std::vector<Wrench> filtered_integral(const Record& r, double tc) {
  std::vector<Wrench> out(r.motion.size(), Wrench::Zero());
  if (r.motion.empty()) return out;
  Wrench c = Wrench::Zero(), f = Wrench::Zero(), acc = Wrench::Zero();
  std::size_t j = 0;
  // Targets before the first sample set the state there (the lag run up to it).
  double t = r.targets.empty() ? r.motion[0].t : std::min(r.targets[0].t, r.motion[0].t);
  const auto advance = [&](double to) {
    const double dt = to - t;
    if (dt <= 0) return;
    const double e = tc > 0 ? std::exp(-dt / tc) : 0.0;
    const double integ = tc > 0 ? tc * (1 - e) : 0.0;
    acc += c * dt + (f - c) * integ;
    f = c + (f - c) * e;
    t = to;
  };
  bool started = false;
  for (std::size_t k = 0; k < r.motion.size(); ++k) {
    const double tk = r.motion[k].t;
    while (j < r.targets.size() && r.targets[j].t <= tk) {
      advance(r.targets[j].t);
      c = r.targets[j].tau;
      ++j;
    }
    advance(tk);
    if (!started) {  // integrals count from the first sample
      acc.setZero();
      started = true;
    }
    out[k] = acc;
  }
  return out;
}

// The wrench target in force at each motion sample (for the window selection).
std::vector<Wrench> target_at_samples(const Record& r) {
  std::vector<Wrench> out(r.motion.size(), Wrench::Zero());
  Wrench c = Wrench::Zero();
  std::size_t j = 0;
  for (std::size_t k = 0; k < r.motion.size(); ++k) {
    while (j < r.targets.size() && r.targets[j].t <= r.motion[k].t) c = r.targets[j++].tau;
    out[k] = c;
  }
  return out;
}

struct Window {
  std::size_t a, b;
};

std::vector<Window> windows_for(const Record& r, int axis, const IdentifyOptions& o,
                                const std::vector<Wrench>& tgt) {
  std::vector<Window> out;
  const auto& m = r.motion;
  std::size_t a = 0;
  while (a + 1 < m.size()) {
    std::size_t b = a + 1;
    bool gap = false;
    while (b < m.size() && m[b].t - m[a].t < o.window_s - 1e-9) {
      gap |= m[b].t - m[b - 1].t > 0.5;
      ++b;
    }
    if (b >= m.size()) break;
    gap |= m[b].t - m[b - 1].t > 0.5;
    bool driven = false, quiet = true;
    for (std::size_t k = a; k <= b; ++k) {
      for (int x = 0; x < kAxes; ++x) {
        const double w = std::fabs(tgt[k][kWrenchIndex[x]]);
        const double v = std::fabs(m[k].nu[static_cast<std::size_t>(kNuIndex[x])]);
        if (x == axis) {
          driven |= w > o.driven_n || v > o.quiet_velocity;
        } else {
          // A buoyant ROV rising at a steady speed does not disturb the other axes (no heave
          // coupling without roll or pitch rates): heave's velocity is not held against them.
          quiet &= w < o.quiet_wrench_n && (x == kHeave || v < o.quiet_velocity);
        }
      }
    }
    if (!gap && driven && quiet) out.push_back({a, b});
    a = b;
  }
  return out;
}

struct Fit {
  Eigen::VectorXd theta;
  Eigen::MatrixXd cov;
  double rss = 0, yy = 0;
  int n = 0;
};

Fit solve(const Regression& g) {
  Fit f;
  f.n = static_cast<int>(g.y.size());
  const int p = static_cast<int>(g.a.cols());
  // Columns scaled to unit norm: the normal equations stay well conditioned.
  Eigen::VectorXd s = g.a.colwise().norm().transpose();
  for (int i = 0; i < p; ++i) s[i] = s[i] > 0 ? s[i] : 1.0;
  const Eigen::MatrixXd as = g.a * s.cwiseInverse().asDiagonal();
  const auto qr = as.colPivHouseholderQr();
  const Eigen::VectorXd th = qr.solve(g.y);
  f.theta = th.cwiseQuotient(s);
  const Eigen::VectorXd res = g.y - g.a * f.theta;
  f.rss = res.squaredNorm();
  f.yy = g.y.squaredNorm();
  const double sigma2 = f.n > p ? f.rss / (f.n - p) : 0.0;
  const Eigen::MatrixXd ata = as.transpose() * as;
  const Eigen::MatrixXd inv = ata.ldlt().solve(Eigen::MatrixXd::Identity(p, p));
  f.cov = sigma2 * (s.cwiseInverse().asDiagonal() * inv * s.cwiseInverse().asDiagonal());
  return f;
}

int n_params(int axis, const IdentifyOptions& o) {
  return axis == kHeave && o.heave_bias ? 4 : 3;
}

}  // namespace

Regression regression(const Record& r, int axis, double tc, const IdentifyOptions& o) {
  Regression g;
  const auto tgt = target_at_samples(r);
  const auto win = windows_for(r, axis, o, tgt);
  const auto integ = filtered_integral(r, tc);
  const int p = n_params(axis, o);
  g.a.resize(static_cast<Eigen::Index>(win.size()), p);
  g.y.resize(static_cast<Eigen::Index>(win.size()));
  const auto vi = static_cast<std::size_t>(kNuIndex[axis]);
  const int wi = kWrenchIndex[axis];
  for (std::size_t i = 0; i < win.size(); ++i) {
    const auto [a, b] = win[i];
    double s1 = 0, s2 = 0;
    for (std::size_t k = a; k < b; ++k) {
      const double dt = r.motion[k + 1].t - r.motion[k].t;
      const double v0 = r.motion[k].nu[vi], v1 = r.motion[k + 1].nu[vi];
      s1 += 0.5 * dt * (v0 + v1);
      s2 += 0.5 * dt * (std::fabs(v0) * v0 + std::fabs(v1) * v1);
    }
    const auto row = static_cast<Eigen::Index>(i);
    g.a(row, 0) = r.motion[b].nu[vi] - r.motion[a].nu[vi];
    g.a(row, 1) = s1;
    g.a(row, 2) = s2;
    if (p == 4) g.a(row, 3) = -(r.motion[b].t - r.motion[a].t);
    g.y(row) = integ[b][wi] - integ[a][wi];
  }
  return g;
}

Identified identify(const Record& r, const IdentifyOptions& o) {
  Identified out;
  out.samples = static_cast<int>(r.motion.size());
  // Which axes have enough windows (independent of the time constant).
  const auto tgt = target_at_samples(r);
  std::array<bool, kAxes> use{};
  for (int x = 0; x < kAxes; ++x) {
    const auto n = static_cast<int>(windows_for(r, x, o, tgt).size());
    auto& am = out.axis[static_cast<std::size_t>(x)];
    am.windows = n;
    bool driven = false;
    for (const auto& w : tgt) driven |= std::fabs(w[kWrenchIndex[x]]) > o.driven_n;
    if (!driven) {
      am.why = "not driven (no wrench target above " + format_number(o.driven_n) + " N)";
    } else if (n < n_params(x, o) + 3) {
      am.why = "only " + std::to_string(n) + " windows with this axis alone driven";
    } else {
      use[static_cast<std::size_t>(x)] = true;
    }
  }
  const auto objective = [&](double tc, std::array<Fit, kAxes>* fits) {
    double j = 0;
    for (int x = 0; x < kAxes; ++x) {
      if (!use[static_cast<std::size_t>(x)]) continue;
      const Fit f = solve(regression(r, x, tc, o));
      j += f.yy > 0 ? f.rss / f.yy : 0.0;
      if (fits != nullptr) (*fits)[static_cast<std::size_t>(x)] = f;
    }
    return j;
  };
  bool any = false;
  for (const bool u : use) any |= u;
  if (!any) return out;

  // Scan log T, then golden section in the best bracket.
  constexpr int kScan = 41;
  const double l0 = std::log(o.time_constant_min_s), l1 = std::log(o.time_constant_max_s);
  std::array<double, kScan> js{};
  int best = 0;
  for (int i = 0; i < kScan; ++i) {
    js[static_cast<std::size_t>(i)] =
        objective(std::exp(l0 + (l1 - l0) * i / (kScan - 1)), nullptr);
    if (js[static_cast<std::size_t>(i)] < js[static_cast<std::size_t>(best)]) best = i;
  }
  double lo = l0 + (l1 - l0) * std::max(best - 1, 0) / (kScan - 1);
  double hi = l0 + (l1 - l0) * std::min(best + 1, kScan - 1) / (kScan - 1);
  const double gr = (std::sqrt(5.0) - 1) / 2;
  double c = hi - gr * (hi - lo), d = lo + gr * (hi - lo);
  double jc = objective(std::exp(c), nullptr), jd = objective(std::exp(d), nullptr);
  for (int it = 0; it < 40; ++it) {
    if (jc < jd) {
      hi = d;
      d = c;
      jd = jc;
      c = hi - gr * (hi - lo);
      jc = objective(std::exp(c), nullptr);
    } else {
      lo = c;
      c = d;
      jc = jd;
      d = lo + gr * (hi - lo);
      jd = objective(std::exp(d), nullptr);
    }
  }
  const double tc = std::exp(0.5 * (lo + hi));
  std::array<Fit, kAxes> fits;
  objective(tc, &fits);
  out.time_constant = tc;

  // 95 % interval: sum over axes of n ln(rss(T) / rss(T*)) <= 3.84.
  const auto lr = [&](double t) {
    double s = 0;
    for (int x = 0; x < kAxes; ++x) {
      if (!use[static_cast<std::size_t>(x)]) continue;
      const Fit f = solve(regression(r, x, t, o));
      const Fit& b = fits[static_cast<std::size_t>(x)];
      if (b.rss > 0) s += b.n * std::log(f.rss / b.rss);
    }
    return s;
  };
  out.time_constant_low = tc;
  while (out.time_constant_low > o.time_constant_min_s && lr(out.time_constant_low / 1.01) <= 3.84)
    out.time_constant_low /= 1.01;
  out.time_constant_high = tc;
  while (out.time_constant_high < o.time_constant_max_s &&
         lr(out.time_constant_high * 1.01) <= 3.84)
    out.time_constant_high *= 1.01;

  for (int x = 0; x < kAxes; ++x) {
    if (!use[static_cast<std::size_t>(x)]) continue;
    const Fit& f = fits[static_cast<std::size_t>(x)];
    auto& am = out.axis[static_cast<std::size_t>(x)];
    am.identified = true;
    am.windows = f.n;
    am.unexplained = f.yy > 0 ? f.rss / f.yy : 0.0;
    Estimate* e[] = {&am.mass, &am.linear, &am.quadratic, &am.bias};
    for (Eigen::Index i = 0; i < f.theta.size(); ++i) {
      e[i]->value = f.theta[i];
      e[i]->std = std::sqrt(std::max(f.cov(i, i), 0.0));
    }
  }
  return out;
}

}  // namespace tiller::tune
