// The bounded solver: largest scale along the minimum-norm pattern, the bounded simplex over the
// null space, the zonotope facets' largest scale, a feasible start, and how the thrust is chosen
// among those making the achieved wrench.
#include "allocation/allocator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "allocation/detail.hpp"

namespace tiller {

using namespace allocation_detail;

double Allocator::max_scale(const Group& g, const ThrustVec& a, const ThrustVec& b) const {
  double mu = kInf;
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto i = static_cast<std::size_t>(g.idx[k]);
    const auto kk = static_cast<Eigen::Index>(k);
    const double lo = lo_[i], hi = hi_[i];
    if (b(kk) < lo * (1 + 1e-12) || b(kk) > hi * (1 + 1e-12)) return -1.0;
    if (a(kk) > 0) mu = std::min(mu, (hi - b(kk)) / a(kk));
    if (a(kk) < 0) mu = std::min(mu, (lo - b(kk)) / a(kk));
  }
  return std::max(mu, 0.0);
}

Allocator::Lp Allocator::make_lp(const Eigen::MatrixXd& a,
                                 const std::array<double, kMaxThrusters>& lo,
                                 const std::array<double, kMaxThrusters>& hi) {
  Lp lp;
  lp.m = static_cast<int>(a.rows());
  lp.n = static_cast<int>(a.cols());
  lp.lo = lo;
  lp.hi = hi;
  // Starting basis: the first columns that add rank (A has full row rank by construction).
  std::vector<int> cols;
  for (int j = 0; j < lp.n && static_cast<int>(cols.size()) < lp.m; ++j) {
    std::vector<int> trial = cols;
    trial.push_back(j);
    std::vector<int> rows(static_cast<std::size_t>(lp.m));
    for (int r = 0; r < lp.m; ++r) rows[static_cast<std::size_t>(r)] = r;
    if (rank_of(rows_cols(a, rows, trial)) > static_cast<int>(cols.size())) cols = trial;
  }
  if (static_cast<int>(cols.size()) != lp.m)
    throw std::logic_error("allocation LP: rows of the effectiveness matrix are dependent");
  Eigen::MatrixXd ab(lp.m, lp.m);
  for (int k = 0; k < lp.m; ++k) {
    lp.basis[static_cast<std::size_t>(k)] = cols[static_cast<std::size_t>(k)];
    ab.col(k) = a.col(cols[static_cast<std::size_t>(k)]);
  }
  const Eigen::MatrixXd inv = ab.fullPivLu().inverse();
  const Eigen::MatrixXd t0 = inv * a;
  for (int r = 0; r < lp.m; ++r) {
    const auto rr = static_cast<std::size_t>(r);
    for (int k = 0; k < lp.m; ++k) lp.binv0[rr][static_cast<std::size_t>(k)] = inv(r, k);
    for (int j = 0; j < lp.n; ++j) lp.t0[rr][static_cast<std::size_t>(j)] = t0(r, j);
    for (int k = 0; k < lp.m; ++k)  // exact identity on the basis columns
      lp.t0[rr][static_cast<std::size_t>(cols[static_cast<std::size_t>(k)])] = r == k ? 1 : 0;
  }
  return lp;
}

// Bounded primal simplex on the tableau of [A | -d/|d|] (m <= 6 rows, n + 1 <= 17 columns,
// fixed-size arrays). Start: f0 (nonbasic values anywhere within their bounds) and mu = 0; the
// basic variables are f0's own values since A f0 = A f0. Bland's rule (smallest index enters,
// smallest index leaves among ties) rules out cycling; every step keeps the point feasible.
double Allocator::lp_max_scale(const Lp& lp, const ThrustVec& f0, const Small& d, double cap,
                               ThrustVec& f) {
  constexpr double kEps = 1e-10, kPiv = 1e-9, kTol = 1e-9;
  constexpr int kCols = kMaxThrusters + 1;
  const int m = lp.m, n = lp.n, mu = n;
  double dn2 = 0;
  for (int k = 0; k < m; ++k) dn2 += d(k) * d(k);
  if (!(dn2 > 0)) {
    f = f0;
    return cap;
  }
  const double dn = std::sqrt(dn2);
  double t[6][kCols];
  double x[kCols], lo[kCols], hi[kCols];
  int basic[6];
  bool is_basic[kCols] = {};
  for (int i = 0; i < m; ++i) {
    const auto ii = static_cast<std::size_t>(i);
    for (int j = 0; j < n; ++j) t[i][j] = lp.t0[ii][static_cast<std::size_t>(j)];
    double c = 0;
    for (int k = 0; k < m; ++k) c += lp.binv0[ii][static_cast<std::size_t>(k)] * d(k);
    t[i][mu] = -c / dn;
    basic[i] = lp.basis[ii];
    is_basic[basic[i]] = true;
  }
  for (int j = 0; j < n; ++j) {
    x[j] = f0(j);
    lo[j] = lp.lo[static_cast<std::size_t>(j)];
    hi[j] = lp.hi[static_cast<std::size_t>(j)];
  }
  x[mu] = 0;
  lo[mu] = 0;
  hi[mu] = cap * dn;
  int mu_row = -1;
  bool unbounded = false;
  for (int iter = 0; iter < 8 * kCols; ++iter) {
    // Entering: smallest index whose move raises mu (mu itself while it is nonbasic).
    int enter = -1;
    double s = 0;
    if (mu_row < 0) {
      if (x[mu] < hi[mu] - kTol) {
        enter = mu;
        s = 1;
      }
    } else {
      const double* row = t[mu_row];
      for (int j = 0; j < n; ++j) {
        if (is_basic[j]) continue;
        const double r = -row[j];
        if (r > kEps && x[j] < hi[j] - kTol) {
          enter = j;
          s = 1;
          break;
        }
        if (r < -kEps && x[j] > lo[j] + kTol) {
          enter = j;
          s = -1;
          break;
        }
      }
    }
    if (enter < 0) break;  // optimal
    double step = s > 0 ? hi[enter] - x[enter] : x[enter] - lo[enter];
    int leave = -1;
    for (int i = 0; i < m; ++i) {
      const double alpha = s * t[i][enter];  // x[basic[i]] changes by -alpha per unit step
      const int b = basic[i];
      double lim;
      if (alpha > kPiv)
        lim = (x[b] - lo[b]) / alpha;
      else if (alpha < -kPiv)
        lim = (hi[b] - x[b]) / -alpha;
      else
        continue;
      lim = std::max(lim, 0.0);
      if (lim < step || (lim == step && leave >= 0 && b < basic[leave])) {
        step = lim;
        leave = i;
      }
    }
    if (!std::isfinite(step)) {  // unbounded along d (cap = inf)
      unbounded = true;
      break;
    }
    x[enter] += s * step;
    for (int i = 0; i < m; ++i) x[basic[i]] -= s * t[i][enter] * step;
    if (leave < 0) {  // the entering variable reached its own other bound
      x[enter] = s > 0 ? hi[enter] : lo[enter];
      continue;
    }
    const int b = basic[leave];
    x[b] = s * t[leave][enter] > 0 ? lo[b] : hi[b];
    const double inv = 1.0 / t[leave][enter];
    double* prow = t[leave];
    for (int j = 0; j <= n; ++j) prow[j] *= inv;
    prow[enter] = 1.0;
    for (int i = 0; i < m; ++i) {
      if (i == leave) continue;
      const double c = t[i][enter];
      if (c == 0.0) continue;
      for (int j = 0; j <= n; ++j) t[i][j] -= c * prow[j];
      t[i][enter] = 0.0;
    }
    is_basic[b] = false;
    is_basic[enter] = true;
    basic[leave] = enter;
    if (enter == mu)
      mu_row = leave;
    else if (b == mu)
      mu_row = -1;
  }
  f.resize(n);
  for (int j = 0; j < n; ++j) f(j) = std::clamp(x[j], lo[j], hi[j]);
  if (unbounded) return kInf;
  return std::min(cap, x[mu] / dn);
}

Allocator::Small Allocator::group_wrench(const Group& g, const ThrustVec& fg) {
  const auto na = static_cast<Eigen::Index>(g.axes.size());
  Small w = Small::Zero(na);
  for (Eigen::Index r = 0; r < na; ++r)
    for (std::size_t k = 0; k < g.idx.size(); ++k)
      w(r) += g.rows(r, g.idx[k]) * fg(static_cast<Eigen::Index>(k));
  return w;
}

double Allocator::facet_max_scale(const Group& g, const Small& c, const Small& d, double cap) {
  const auto m = static_cast<std::size_t>(g.axes.size());
  double dmax = 0;
  bool c_zero = true;
  for (std::size_t r = 0; r < m; ++r) {
    dmax = std::max(dmax, std::abs(d(static_cast<Eigen::Index>(r))));
    c_zero = c_zero && c(static_cast<Eigen::Index>(r)) == 0.0;
  }
  const double tiny = 1e-12 * dmax;
  // min over facets with n.d > 0 of (h - n.c) / (n.d), below cap: a facet is divided only when
  // it is below the best so far.
  double best = cap;
  for (std::size_t f = 0; f < g.facet_h.size(); ++f) {
    double nd = 0;
    for (std::size_t r = 0; r < m; ++r) nd += g.facet_n[r][f] * d(static_cast<Eigen::Index>(r));
    if (!(nd > tiny)) continue;
    double slack = g.facet_h[f];
    if (!c_zero)
      for (std::size_t r = 0; r < m; ++r)
        slack -= g.facet_n[r][f] * c(static_cast<Eigen::Index>(r));
    if (slack < best * nd) best = slack / nd;
  }
  return std::max(best, 0.0);
}

// Levels in order, each as far as the facets allow from the wrench so far (every other axis held
// where it is), in passes until nothing moves (at most 4). The slack of every facet,
// h - n . (wrench so far), is kept up to date as levels move, so a one-axis level looks only at
// the facets whose normal leans along its axis that way.
void Allocator::prioritised_facets(const Group& g, const Small& target, const Small& comp,
                                   Small& got, Small& left) const {
  const auto m = static_cast<std::size_t>(g.axes.size());
  const std::size_t nf = g.facet_h.size();
  double slack[kMaxFacets];
  for (std::size_t f = 0; f < nf; ++f) {
    double s = g.facet_h[f];
    for (std::size_t r = 0; r < m; ++r) s += g.facet_n[r][f] * comp(static_cast<Eigen::Index>(r));
    slack[f] = s;
  }
  got.setZero();
  left = target;
  std::array<int, 6> solved_at;  // a level is solved again only if another moved since
  solved_at.fill(-1);
  int changes = 0;
  for (int pass = 0; pass < 4; ++pass) {
    bool progress = false;
    for (std::size_t li = 0; li < g.levels.size(); ++li) {
      const auto& level = g.levels[li];
      if (solved_at[li] == changes) continue;
      solved_at[li] = changes;
      double dmax = 0;
      for (int k : level) dmax = std::max(dmax, std::abs(left(k)));
      if (dmax <= 0.0) continue;
      double best = 1.0;
      if (level.size() == 1) {
        const auto k = static_cast<std::size_t>(level[0]);
        const double dk = left(level[0]);
        for (int f : g.facet_by_axis[k][dk > 0 ? 0 : 1]) {
          const double nd = g.facet_n[k][static_cast<std::size_t>(f)] * dk;
          if (slack[f] < best * nd) best = slack[f] / nd;
        }
      } else {
        for (std::size_t f = 0; f < nf; ++f) {
          double nd = 0;
          for (int k : level) nd += g.facet_n[static_cast<std::size_t>(k)][f] * left(k);
          if (nd > 1e-12 * dmax && slack[f] < best * nd) best = slack[f] / nd;
        }
      }
      const double alpha = std::max(best, 0.0);
      if (!(alpha > 1e-12)) continue;
      for (std::size_t f = 0; f < nf; ++f) {
        double nd = 0;
        for (int k : level) nd += g.facet_n[static_cast<std::size_t>(k)][f] * left(k);
        slack[f] -= alpha * nd;
      }
      for (int k : level) {
        got(k) += alpha * left(k);
        left(k) = alpha == 1.0 ? 0.0 : left(k) * (1.0 - alpha);
      }
      ++changes;
      solved_at[li] = changes;
      progress = true;
    }
    if (!progress) break;
  }
}

bool Allocator::feasible_start(const Group& g, const ThrustVec& b, ThrustVec& f0) const {
  f0 = b;
  bool fits = true;
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    f0(kk) = std::clamp(b(kk), g.lp.lo[k], g.lp.hi[k]);
    fits = fits && f0(kk) == b(kk);
  }
  if (fits) return true;
  // Phase 1 with the same solver: from the clipped point toward b's wrench.
  const auto na = static_cast<Eigen::Index>(g.axes.size());
  Small d = Small::Zero(na);
  for (Eigen::Index r = 0; r < na; ++r)
    for (std::size_t k = 0; k < g.idx.size(); ++k)
      d(r) += g.rows(r, g.idx[k]) *
              (b(static_cast<Eigen::Index>(k)) - f0(static_cast<Eigen::Index>(k)));
  ThrustVec f;
  const double reach = lp_max_scale(g.lp, f0, d, 1.0, f);
  if (reach < 1.0 - 1e-9) return false;
  f0 = f;
  return true;
}

// The thrust nearest the minimum-norm one among those making the same wrench within limits:
// f = f_mn + N z with N the orthonormal null-space basis (B_g N = 0, f_mn orthogonal to it), so
// |f|^2 = |f_mn|^2 + |z|^2 and z is the point nearest the origin of the polytope
// {z : lo - pad <= f_mn + N z <= hi + pad} in k = null_dim dimensions: a least-distance problem,
// solved by the dual active-set method of Goldfarb and Idnani (1983) with the identity Hessian.
// It starts at z = 0 (the minimum-norm point, optimal without constraints), adds the most violated
// constraint and moves along its normal projected off the active ones, dropping an active
// constraint whose multiplier would turn negative; every step keeps the multipliers feasible and
// lowers the violation, and the active normals stay linearly independent (at most k). The answer
// is unique (a strictly convex problem), so it moves continuously with the demand. The bounds are
// widened by `pad` (1e-12 of the group's largest limit) so that a wrench on the boundary of what
// the group can do, off by a rounding error, still has a point; finish() clamps it. False (z as
// far as it got) only if the wrench is outside the group's reach by more than that.
bool Allocator::nearest_within_limits(const Group& g, ThrustVec& f) const {
  const int n = static_cast<int>(g.idx.size()), k = g.null_dim;
  const double pad = g.pad, tol = 0.1 * g.pad;
  // Constraint c (0 <= c < 2n) of thruster j = c % n: upper (c < n) N_j z <= hi_j + pad - f_j,
  // lower -N_j z <= f_j - lo_j + pad. Violation at z: s_c = +-(N_j z + f_j) - limit.
  double v[kMaxThrusters];  // thrust at the current z
  for (int j = 0; j < n; ++j) v[j] = f(j);
  auto violation = [&](int c) {
    const int j = c % n;
    const auto jj = static_cast<std::size_t>(j);
    return c < n ? v[j] - (g.lp.hi[jj] + pad) : (g.lp.lo[jj] - pad) - v[j];
  };
  if (k == 1) {  // an interval on the line: z = the clamp of 0 into it
    double lo_z = -kInf, hi_z = kInf;
    for (int j = 0; j < n; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      const double a = g.null(j, 0);
      if (std::abs(a) <= 1e-12) continue;
      const double z1 = (g.lp.lo[jj] - pad - v[j]) / a, z2 = (g.lp.hi[jj] + pad - v[j]) / a;
      lo_z = std::max(lo_z, std::min(z1, z2));
      hi_z = std::min(hi_z, std::max(z1, z2));
    }
    const double z = lo_z > hi_z ? 0.5 * (lo_z + hi_z) : std::clamp(0.0, lo_z, hi_z);
    for (int j = 0; j < n; ++j) f(j) += g.null(j, 0) * z;
    return lo_z <= hi_z;
  }
  double z[kMaxThrusters] = {}, u[kMaxThrusters], r[kMaxThrusters], pd[kMaxThrusters];
  int act[kMaxThrusters], na = 0;
  double gram[kMaxThrusters][kMaxThrusters], ell[kMaxThrusters][kMaxThrusters];
  auto normal = [&](int c, int d) { return c < n ? g.null(c, d) : -g.null(c - n, d); };
  bool active[2 * kMaxThrusters] = {};
  bool ok = false, stuck = false;
  for (int outer = 0; outer < 4 * n + 8 && !stuck; ++outer) {
    int q = -1;
    double worst = tol;
    for (int c = 0; c < 2 * n; ++c) {
      if (active[c]) continue;
      const double rn = g.null_row_norm[static_cast<std::size_t>(c % n)];
      if (rn <= 1e-12) continue;  // fixed by the wrench alone: nothing to choose
      const double s = violation(c) / rn;
      if (s > worst) {
        worst = s;
        q = c;
      }
    }
    if (q < 0) {
      ok = true;
      break;
    }
    double uq = 0;
    for (int inner = 0; inner <= k + 1; ++inner) {
      // r = (A^T A)^-1 A^T a_q over the active normals A (Cholesky of their Gram matrix), and
      // pd = a_q - A r, the part of a_q off the active normals.
      double atq[kMaxThrusters];
      for (int p = 0; p < na; ++p) {
        atq[p] = 0;
        for (int d = 0; d < k; ++d) atq[p] += normal(act[p], d) * normal(q, d);
      }
      for (int p = 0; p < na; ++p) {
        for (int e = 0; e <= p; ++e) {
          double sum = 0;
          for (int d = 0; d < k; ++d) sum += normal(act[p], d) * normal(act[e], d);
          gram[p][e] = sum;
        }
      }
      for (int p = 0; p < na; ++p) {  // Cholesky, lower
        for (int e = 0; e <= p; ++e) {
          double sum = gram[p][e];
          for (int h = 0; h < e; ++h) sum -= ell[p][h] * ell[e][h];
          ell[p][e] = p == e ? std::sqrt(std::max(sum, 1e-300)) : sum / ell[e][e];
        }
      }
      for (int p = 0; p < na; ++p) {  // forward
        double sum = atq[p];
        for (int h = 0; h < p; ++h) sum -= ell[p][h] * r[h];
        r[p] = sum / ell[p][p];
      }
      for (int p = na - 1; p >= 0; --p) {  // back
        double sum = r[p];
        for (int h = p + 1; h < na; ++h) sum -= ell[h][p] * r[h];
        r[p] = sum / ell[p][p];
      }
      double pd2 = 0;
      for (int d = 0; d < k; ++d) {
        double x = normal(q, d);
        for (int p = 0; p < na; ++p) x -= normal(act[p], d) * r[p];
        pd[d] = x;
        pd2 += x * x;
      }
      const double sq = violation(q);
      const double t1 = pd2 > 1e-20 ? sq / pd2 : kInf;
      double t2 = kInf;
      int drop = -1;
      for (int p = 0; p < na; ++p)
        if (r[p] > 1e-12 && u[p] / r[p] < t2) {
          t2 = u[p] / r[p];
          drop = p;
        }
      const double t = std::min(t1, t2);
      if (!std::isfinite(t)) {  // no point satisfies the active constraints and q
        stuck = true;
        break;
      }
      for (int d = 0; d < k; ++d) z[d] -= t * pd[d];
      for (int p = 0; p < na; ++p) u[p] -= t * r[p];
      uq += t;
      for (int j = 0; j < n; ++j) {
        double x = f(j);
        for (int d = 0; d < k; ++d) x += g.null(j, d) * z[d];
        v[j] = x;
      }
      if (t1 <= t2) {  // q satisfied: it joins the active set
        act[na] = q;
        u[na] = uq;
        ++na;
        active[q] = true;
        break;
      }
      active[act[drop]] = false;
      for (int p = drop; p + 1 < na; ++p) {  // a multiplier reached 0: that one leaves
        act[p] = act[p + 1];
        u[p] = u[p + 1];
      }
      --na;
    }
  }
  for (int j = 0; j < n; ++j) f(j) = v[j];
  return ok;
}

void Allocator::clamp_group(const Group& g, ThrustVec& f) const {
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto i = static_cast<std::size_t>(g.idx[k]);
    f(static_cast<Eigen::Index>(k)) = std::clamp(f(static_cast<Eigen::Index>(k)), lo_[i], hi_[i]);
  }
}

}  // namespace tiller
