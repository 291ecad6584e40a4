// The bounded solver: largest scale along the minimum-norm pattern, the bounded simplex over the
// null space, the zonotope facets' largest scale and prioritised levels over them, a feasible
// start. (The thrust for a wrench: nearest.cpp.)
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
  // Row by row over contiguous facet normals (facet_n[r]), a row whose coefficient is 0 skipped:
  // the first group has no compensation at all.
  // The normals are padded with zeros to a multiple of 4 facets, so the updates run four at a
  // time (two SSE2 operations each, straight-line code the compiler vectorises at -O2).
  const std::size_t nf4 = (nf + 3) & ~std::size_t{3};
  double slack[kMaxFacets];
  std::copy(g.facet_h.begin(), g.facet_h.end(), slack);
  std::fill(slack + nf, slack + nf4, 0.0);
  auto add = [&](const double* n, double c) {
    for (std::size_t f = 0; f < nf4; f += 4) {
      slack[f] += n[f] * c;
      slack[f + 1] += n[f + 1] * c;
      slack[f + 2] += n[f + 2] * c;
      slack[f + 3] += n[f + 3] * c;
    }
  };
  for (std::size_t r = 0; r < m; ++r) {
    const double c = comp(static_cast<Eigen::Index>(r));
    if (c != 0.0) add(g.facet_n[r].data(), c);
  }
  got.setZero();
  left = target;
  std::array<int, 6> solved_at;  // a level is solved again only if another moved since
  solved_at.fill(-1);
  // A one-axis level's blocking facet (position in its facet list) from its last solve: while
  // that facet has no slack the level cannot move (its room is at most that facet's), so it is
  // not scanned again. Its direction keeps its sign (left only shrinks), so the list stays.
  std::array<int, 6> blocker;
  blocker.fill(-1);
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
        // n . d = |n_k| |d_k| on these facets: the room is min(slack / |n_k|) / |d_k|, one
        // division per level.
        const auto k = static_cast<std::size_t>(level[0]);
        const double dk = left(level[0]);
        const auto& idx = g.facet_by_axis[k][dk > 0 ? 0 : 1];
        const double* inv = g.facet_inv_by_axis[k][dk > 0 ? 0 : 1].data();
        const int bi = blocker[li];
        const auto bu = static_cast<std::size_t>(bi);
        if (bi >= 0 && slack[idx[bu]] * inv[bu] <= 1e-12 * std::abs(dk)) continue;  // still blocked
        double room = kInf;
        std::size_t arg = 0;
        for (std::size_t i = 0; i < idx.size(); ++i) {
          const double r = slack[idx[i]] * inv[i];
          if (r < room) {
            room = r;
            arg = i;
          }
        }
        best = std::min(1.0, room / std::abs(dk));
        if (best < 1.0) blocker[li] = static_cast<int>(arg);
      } else {
        for (std::size_t f = 0; f < nf; ++f) {
          double nd = 0;
          for (int k : level) nd += g.facet_n[static_cast<std::size_t>(k)][f] * left(k);
          if (nd > 1e-12 * dmax && slack[f] < best * nd) best = slack[f] / nd;
        }
      }
      const double alpha = std::max(best, 0.0);
      if (!(alpha > 1e-12)) continue;
      for (int k : level) {
        const double c = alpha * left(k);
        if (c != 0.0) add(g.facet_n[static_cast<std::size_t>(k)].data(), -c);
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

void Allocator::clamp_group(const Group& g, ThrustVec& f) const {
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto i = static_cast<std::size_t>(g.idx[k]);
    f(static_cast<Eigen::Index>(k)) = std::clamp(f(static_cast<Eigen::Index>(k)), lo_[i], hi_[i]);
  }
}

}  // namespace tiller
