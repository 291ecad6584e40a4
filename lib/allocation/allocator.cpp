#include "allocation/allocator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tiller {
namespace {

constexpr std::array<int, 6> kRankOrder = {0, 1, 2, 5, 4, 3};  // X Y Z N M K
constexpr double kInf = std::numeric_limits<double>::infinity();

int rank_of(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 0;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
  lu.setThreshold(1e-9);
  return static_cast<int>(lu.rank());
}

Eigen::MatrixXd rows_cols(const Eigen::MatrixXd& b, const std::vector<int>& rows,
                          const std::vector<int>& cols) {
  Eigen::MatrixXd m(rows.size(), cols.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < cols.size(); ++c)
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = b(rows[r], cols[c]);
  return m;
}

std::vector<int> all_cols(int n) {
  std::vector<int> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = i;
  return v;
}

}  // namespace

Allocator::Allocator(const Vehicle& vehicle)
    : vehicle_(vehicle), n_(vehicle.size()), strategy_(vehicle.allocation.strategy) {
  const std::string who = "vehicle '" + vehicle.name + "': ";
  const std::string file =
      (vehicle.source_file.empty() ? std::string("<vehicle '" + vehicle.name + "'>")
                                   : vehicle.source_file) +
      ": ";
  auto group_key = [&](const std::string& gname) {  // thrusters[i].group of its first thruster
    for (int i = 0; i < vehicle.size(); ++i)
      if (vehicle.thrusters[static_cast<std::size_t>(i)].group == gname)
        return "thrusters[" + std::to_string(i) + "].group";
    return std::string("thrusters[].group");
  };
  if (n_ < 1 || n_ > kMaxThrusters)
    throw std::invalid_argument(file + "thrusters: expected 1 to 16 thrusters (" + who + ")");
  b_full_ = vehicle.effectiveness();
  b_ = b_full_;
  for (int i = 0; i < n_; ++i) {
    const Thruster& t = vehicle.thrusters[static_cast<std::size_t>(i)];
    lo_[static_cast<std::size_t>(i)] = t.thrust_min();
    hi_[static_cast<std::size_t>(i)] = t.thrust_max();
  }
  // Actuated axes, greedy by rank.
  std::vector<int> actuated;
  const std::vector<int> cols = all_cols(n_);
  for (int ax : kRankOrder) {
    std::vector<int> trial = actuated;
    trial.push_back(ax);
    if (rank_of(rows_cols(b_full_, trial, cols)) > static_cast<int>(actuated.size()))
      actuated = trial;
  }
  for (int ax = 0; ax < 6; ++ax)
    unactuated_[static_cast<std::size_t>(ax)] =
        std::find(actuated.begin(), actuated.end(), ax) == actuated.end();

  // Groups in order of first appearance; each owns the actuated axes where it adds rank.
  std::vector<Group> groups;
  for (int i = 0; i < n_; ++i) {
    const std::string& gname = vehicle.thrusters[static_cast<std::size_t>(i)].group;
    auto it =
        std::find_if(groups.begin(), groups.end(), [&](const Group& g) { return g.name == gname; });
    if (it == groups.end()) {
      groups.push_back(Group{});
      groups.back().name = gname;
      it = groups.end() - 1;
    }
    it->idx.push_back(i);
  }
  std::array<int, 6> owner;
  owner.fill(-1);
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    Group& g = groups[gi];
    for (int ax : kRankOrder) {
      if (unactuated_[static_cast<std::size_t>(ax)]) continue;
      std::vector<int> trial = g.axes;
      trial.push_back(ax);
      if (rank_of(rows_cols(b_full_, trial, g.idx)) > static_cast<int>(g.axes.size())) {
        if (owner[static_cast<std::size_t>(ax)] >= 0) {
          const std::string& other =
              groups[static_cast<std::size_t>(owner[static_cast<std::size_t>(ax)])].name;
          throw std::invalid_argument(file + group_key(g.name) + ": groups '" + other + "' (" +
                                      group_key(other) + ") and '" + g.name +
                                      "' both act on axis " +
                                      kAxisNames[static_cast<std::size_t>(ax)] +
                                      " independently; expected those thrusters in one group");
        }
        owner[static_cast<std::size_t>(ax)] = static_cast<int>(gi);
        g.axes = trial;
      }
    }
  }
  for (int ax : actuated)
    if (owner[static_cast<std::size_t>(ax)] < 0)
      throw std::invalid_argument(file + "thrusters[].group: axis " +
                                  std::string(kAxisNames[static_cast<std::size_t>(ax)]) +
                                  " needs thrusters of several groups together; expected "
                                  "those thrusters in one group");
  // Solve order: a group that acts on another group's axes goes first.
  auto affects = [&](const Group& a, const Group& b) {
    return rows_cols(b_full_, b.axes, a.idx).cwiseAbs().maxCoeff() > 1e-9;
  };
  std::vector<bool> placed(groups.size(), false);
  for (std::size_t round = 0; round < groups.size(); ++round) {
    bool progress = false;
    for (std::size_t gi = 0; gi < groups.size() && !progress; ++gi) {
      if (placed[gi]) continue;
      bool ready = true;  // no unplaced group acts on gi's axes
      for (std::size_t hi = 0; hi < groups.size(); ++hi)
        if (hi != gi && !placed[hi] && !groups[hi].axes.empty() && affects(groups[hi], groups[gi]))
          ready = false;
      if (ready) {
        placed[gi] = true;
        groups_.push_back(groups[gi]);
        progress = true;
      }
    }
    if (!progress) {
      std::string names;
      for (std::size_t gi = 0; gi < groups.size(); ++gi)
        if (!placed[gi]) names += " '" + groups[gi].name + "' (" + group_key(groups[gi].name) + ")";
      throw std::invalid_argument(file + "thrusters[].group: groups" + names +
                                  " act on each other's axes both ways; expected them merged "
                                  "into one group");
    }
  }
  for (Group& g : groups_) {
    g.rows = rows_cols(b_full_, g.axes, cols);
    if (!g.axes.empty()) {
      const Eigen::MatrixXd bg = rows_cols(b_full_, g.axes, g.idx);
      g.pinv = bg.completeOrthogonalDecomposition().pseudoInverse();
    } else {
      g.pinv.resize(static_cast<Eigen::Index>(g.idx.size()), 0);
    }
    g.null_dim = static_cast<int>(g.idx.size()) - static_cast<int>(g.axes.size());
    if (g.null_dim > 0) {
      std::array<double, kMaxThrusters> glo{}, ghi{};
      for (std::size_t k = 0; k < g.idx.size(); ++k) {
        glo[k] = lo_[static_cast<std::size_t>(g.idx[k])];
        ghi[k] = hi_[static_cast<std::size_t>(g.idx[k])];
      }
      const Eigen::MatrixXd bg = rows_cols(b_full_, g.axes, g.idx);
      g.lp = make_lp(bg, glo, ghi);
      // Facets of the zonotope: normals orthogonal to m - 1 independent generators.
      const int m = static_cast<int>(g.axes.size()), ng = static_cast<int>(g.idx.size());
      double count = 1;  // C(ng, m - 1)
      for (int k = 0; k < m - 1; ++k) count = count * (ng - k) / (k + 1);
      if (2 * count <= static_cast<double>(kMaxFacets)) {
        std::vector<int> pick(static_cast<std::size_t>(std::max(m - 1, 0)));
        auto add = [&](const Eigen::VectorXd& nrm) {
          for (double sgn : {1.0, -1.0}) {
            std::array<double, 7> fct{};
            double h = 0;
            for (int j = 0; j < ng; ++j) {
              const double p = sgn * nrm.dot(bg.col(j));
              h += std::max(p * glo[static_cast<std::size_t>(j)],
                            p * ghi[static_cast<std::size_t>(j)]);
            }
            for (int r = 0; r < m; ++r) fct[static_cast<std::size_t>(r)] = sgn * nrm(r);
            fct[6] = h;
            g.facets.push_back(fct);
          }
        };
        if (m == 1) {
          add(Eigen::VectorXd::Ones(1));
        } else {
          // Every (m - 1)-subset of the generators, in lexicographic order.
          for (int k = 0; k < m - 1; ++k) pick[static_cast<std::size_t>(k)] = k;
          while (true) {
            Eigen::MatrixXd sub(m - 1, m);
            for (int k = 0; k < m - 1; ++k)
              sub.row(k) = bg.col(pick[static_cast<std::size_t>(k)]).transpose();
            Eigen::FullPivLU<Eigen::MatrixXd> lu(sub);
            lu.setThreshold(1e-9);
            if (lu.rank() == m - 1) add(lu.kernel().col(0).normalized());
            int k = m - 2;
            while (k >= 0 && pick[static_cast<std::size_t>(k)] == ng - (m - 1) + k) --k;
            if (k < 0) break;
            ++pick[static_cast<std::size_t>(k)];
            for (int q = k + 1; q < m - 1; ++q)
              pick[static_cast<std::size_t>(q)] = pick[static_cast<std::size_t>(q - 1)] + 1;
          }
        }
      }
    }
    for (const auto& level : vehicle.allocation.priority) {
      std::vector<int> pos;
      for (int ax : level)
        for (std::size_t k = 0; k < g.axes.size(); ++k)
          if (g.axes[k] == ax) pos.push_back(static_cast<int>(k));
      if (!pos.empty()) g.levels.push_back(pos);
    }
  }
  solve_.resize(n_, 6);
  for (int ax = 0; ax < 6; ++ax) solve_.col(ax) = solve_unconstrained(Wrench::Unit(ax));
  // Largest achievable along each axis alone (manual demand scaling).
  for (int ax = 0; ax < 6; ++ax) {
    for (int s = 0; s < 2; ++s) {
      double m = 0;
      if (!unactuated_[static_cast<std::size_t>(ax)]) {
        Wrench e = Wrench::Zero();
        e(ax) = s == 0 ? 1.0 : -1.0;
        const ThrustVec f = solve_unconstrained(e);
        m = kInf;
        for (int i = 0; i < n_; ++i) {
          if (f(i) > 1e-12) m = std::min(m, hi_[static_cast<std::size_t>(i)] / f(i));
          if (f(i) < -1e-12) m = std::min(m, lo_[static_cast<std::size_t>(i)] / f(i));
        }
      }
      axis_max_[static_cast<std::size_t>(s)][static_cast<std::size_t>(ax)] = m;
    }
  }
  // With spare thrusters, the pseudo-inverse pattern is not the largest: the same LP as the
  // allocation, over every actuated axis and every thruster (other actuated axes held at 0).
  if (n_ > static_cast<int>(actuated.size())) {
    const Lp whole = make_lp(rows_cols(b_full_, actuated, cols), lo_, hi_);
    const ThrustVec zero = ThrustVec::Zero(n_);
    ThrustVec f(n_);
    for (std::size_t k = 0; k < actuated.size(); ++k) {
      for (int s = 0; s < 2; ++s) {
        Small d = Small::Zero(static_cast<Eigen::Index>(actuated.size()));
        d(static_cast<Eigen::Index>(k)) = s == 0 ? 1.0 : -1.0;
        axis_max_[static_cast<std::size_t>(s)][static_cast<std::size_t>(actuated[k])] =
            lp_max_scale(whole, zero, d, kInf, f);
      }
    }
  }
  // Explicit mixing matrix.
  if (vehicle.allocation.has_matrix()) {
    matrix_ = true;
    mix_ = vehicle.allocation.matrix;
    mix_axes_ = vehicle.allocation.matrix_axes;
    full_scale_.setOnes();
    for (std::size_t j = 0; j < mix_axes_.size(); ++j) {
      ThrustVec f(n_);
      for (int i = 0; i < n_; ++i) {
        const Thruster& t = vehicle.thrusters[static_cast<std::size_t>(i)];
        const double e = mix_(i, static_cast<Eigen::Index>(j));
        // Commands: the motor's own curve, as if wired the right way round, so that reversing
        // a motor (wiring) does not change what the table sends.
        f(i) = vehicle.allocation.matrix_commands ? t.curve.thrust(std::clamp(e, -1.0, 1.0))
                                                  : e * t.max_forward_n;
      }
      const double w = (b_ * f)(mix_axes_[j]);
      if (!(std::abs(w) > 1e-9))
        throw std::invalid_argument(
            file + "allocation.mixing" +
            (vehicle.allocation.matrix_key.empty() ? std::string()
                                                   : "." + vehicle.allocation.matrix_key) +
            ": column " + std::to_string(j) + " (axis " +
            std::string(kAxisNames[static_cast<std::size_t>(mix_axes_[j])]) +
            ") produces nothing on that axis with this geometry; expected a column whose "
            "thrusters push or turn the vehicle along it (check the rows and the thrusters' "
            "position / direction)");
      full_scale_(mix_axes_[j]) = std::abs(w);
    }
  }
}

const char* Allocator::strategy_name() const {
  return matrix_ ? "matrix" : tiller::strategy_name(strategy_);
}

std::string Allocator::describe() const {
  std::ostringstream os;
  os << vehicle_.name << ": " << n_ << " thrusters, strategy " << strategy_name()
     << ", unactuated:";
  for (int ax = 0; ax < 6; ++ax)
    if (unactuated_[static_cast<std::size_t>(ax)])
      os << ' ' << kAxisNames[static_cast<std::size_t>(ax)];
  for (const Group& g : groups_) {
    os << "\n  group " << g.name << " [";
    for (int i : g.idx) os << ' ' << vehicle_.thrusters[static_cast<std::size_t>(i)].name;
    os << " ] owns";
    for (int ax : g.axes) os << ' ' << kAxisNames[static_cast<std::size_t>(ax)];
    if (g.null_dim > 0 && !matrix_)
      os << ", " << g.null_dim << " spare (null space, used under saturation; " << g.facets.size()
         << " facets)";
  }
  return os.str();
}

ThrustVec Allocator::solve_unconstrained(const Wrench& tau) const {
  ThrustVec f = ThrustVec::Zero(n_);
  for (const Group& g : groups_) {
    const auto na = static_cast<Eigen::Index>(g.axes.size());
    Small r(na);
    for (Eigen::Index k = 0; k < na; ++k) r(k) = tau(g.axes[static_cast<std::size_t>(k)]);
    r -= g.rows * f;
    const ThrustVec fg = g.pinv * r;
    for (std::size_t k = 0; k < g.idx.size(); ++k) f(g.idx[k]) = fg(static_cast<Eigen::Index>(k));
  }
  return f;
}

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

double Allocator::facet_max_scale(const Group& g, const Small& c, const Small& d) {
  const auto m = static_cast<int>(g.axes.size());
  double cc[6], dd[6], dmax = 0;
  for (int r = 0; r < m; ++r) {
    cc[r] = c(r);
    dd[r] = d(r);
    dmax = std::max(dmax, std::abs(dd[r]));
  }
  const double tiny = 1e-12 * dmax;
  // min over facets with n.d > 0 of (h - n.c) / (n.d), kept as a fraction num / den (den > 0)
  // so that only one division is made.
  double num = 1, den = 0;
  for (const auto& f : g.facets) {
    double nd = 0, nc = 0;
    for (int r = 0; r < m; ++r) {
      nd += f[static_cast<std::size_t>(r)] * dd[r];
      nc += f[static_cast<std::size_t>(r)] * cc[r];
    }
    const double h = f[6] - nc;
    if (nd > tiny && (den == 0 || h * den < num * nd)) {
      num = h;
      den = nd;
    }
  }
  if (den == 0) return kInf;
  return std::max(num / den, 0.0);
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

// Cascaded pseudo-inverse from the minimum-norm point: thrusters beyond a limit are fixed at it
// and the rest re-solved (minimum norm) for the same wrench, until everything fits. Depends on
// the wrench alone, and a thruster reaching its limit changes nothing at that moment, so the
// result moves continuously with the demand. False when it runs out of free thrusters.
bool Allocator::cascade(const Group& g, const ThrustVec& f_mn, ThrustVec& f) const {
  const int m = static_cast<int>(g.axes.size()), n = static_cast<int>(g.idx.size());
  const Small w = group_wrench(g, f_mn);
  f = f_mn;
  bool fixed[kMaxThrusters] = {};
  for (int iter = 0; iter < n; ++iter) {
    bool any = false;
    for (int k = 0; k < n; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      const double lo = g.lp.lo[kk], hi = g.lp.hi[kk];
      const double tol = 1e-9 * (1.0 + std::max(hi, -lo));
      if (!fixed[k] && (f(k) > hi + tol || f(k) < lo - tol)) {
        f(k) = std::clamp(f(k), lo, hi);
        fixed[k] = true;
        any = true;
      }
    }
    if (!any) return true;
    // Free thrusters: minimum norm for w - (fixed ones' wrench), f_F = B_F' (B_F B_F')^-1 r.
    Small r = w;
    int nfree = 0;
    for (int k = 0; k < n; ++k) {
      if (!fixed[k]) {
        ++nfree;
        continue;
      }
      for (int a = 0; a < m; ++a) r(a) -= g.rows(a, g.idx[static_cast<std::size_t>(k)]) * f(k);
    }
    if (nfree < m) return false;
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6> gram =
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>::Zero(m, m);
    for (int k = 0; k < n; ++k) {
      if (fixed[k]) continue;
      const int col = g.idx[static_cast<std::size_t>(k)];
      for (int a = 0; a < m; ++a)
        for (int c = 0; c < m; ++c) gram(a, c) += g.rows(a, col) * g.rows(c, col);
    }
    Eigen::LLT<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>> llt(gram);
    if (llt.info() != Eigen::Success) return false;
    const Small y = llt.solve(r);
    for (int k = 0; k < n; ++k) {
      if (fixed[k]) continue;
      const int col = g.idx[static_cast<std::size_t>(k)];
      double v = 0;
      for (int a = 0; a < m; ++a) v += g.rows(a, col) * y(a);
      f(k) = v;
    }
  }
  return false;
}

void Allocator::toward_feasible(const Group& g, const ThrustVec& f_mn, ThrustVec& f_v) const {
  // With one spare direction, the first point within limits on the way from f_mn is the
  // nearest whatever feasible f_v is. With more, the cascade (when it succeeds) is used: the
  // segment toward an LP vertex could jump between vertices as the demand changes.
  if (g.null_dim >= 2) {
    ThrustVec fc;
    if (cascade(g, f_mn, fc)) {
      for (std::size_t k = 0; k < g.idx.size(); ++k)
        fc(static_cast<Eigen::Index>(k)) =
            std::clamp(fc(static_cast<Eigen::Index>(k)), g.lp.lo[k], g.lp.hi[k]);
      f_v = fc;
      return;
    }
  }
  double t = 0;
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    const double a = f_mn(kk), v = f_v(kk);
    if (a > g.lp.hi[k] && a > v) t = std::max(t, (a - g.lp.hi[k]) / (a - v));
    if (a < g.lp.lo[k] && a < v) t = std::max(t, (g.lp.lo[k] - a) / (v - a));
  }
  t = std::min(t, 1.0);
  f_v = f_mn + t * (f_v - f_mn);
}

void Allocator::clamp_group(const Group& g, ThrustVec& f) const {
  for (std::size_t k = 0; k < g.idx.size(); ++k) {
    const auto i = static_cast<std::size_t>(g.idx[k]);
    f(static_cast<Eigen::Index>(k)) = std::clamp(f(static_cast<Eigen::Index>(k)), lo_[i], hi_[i]);
  }
}

void Allocator::neutral(AllocationResult& out) const {
  out.manual = false;
  out.demanded.setZero();
  out.target.setZero();
  out.achieved.setZero();
  out.unallocated.setZero();
  out.axis_reduced.fill(false);
  out.axis_unactuated = unactuated_;
  out.scale = 1.0;
  out.n = n_;
  out.thrust.fill(0.0);
  out.command.fill(0.0);
  out.saturated.fill(false);
}

bool Allocator::allocate(const Wrench& tau, AllocationResult& out) const {
  if (!tau.allFinite() || tau.cwiseAbs().maxCoeff() > kMaxWrenchComponent) {
    neutral(out);
    return false;
  }
  out.manual = false;
  out.demanded = tau;
  out.target = tau;
  out.scale = 1.0;
  if (matrix_) {
    Wrench norm = Wrench::Zero();
    for (int ax : mix_axes_) norm(ax) = tau(ax) / full_scale_(ax);
    allocate_matrix(norm, out);
    return true;
  }
  // Fast path: the exact solution fits every thruster's limits -> every strategy agrees.
  ThrustVec f = solve_ * tau;
  bool fits = true;
  for (int i = 0; i < n_; ++i)
    fits = fits && f(i) <= hi_[static_cast<std::size_t>(i)] &&
           f(i) >= lo_[static_cast<std::size_t>(i)];
  if (fits) {
    finish(f, out);
    return true;
  }
  f.setZero();
  for (const Group& g : groups_) {
    const auto na = static_cast<Eigen::Index>(g.axes.size());
    Small target(na);
    for (Eigen::Index k = 0; k < na; ++k) target(k) = tau(g.axes[static_cast<std::size_t>(k)]);
    const Small comp = g.rows * f;  // what earlier groups already do on these axes
    const ThrustVec b = -(g.pinv * comp);
    ThrustVec fg;
    switch (strategy_) {
      case Strategy::kDirectionPreserving: {
        const ThrustVec a = g.pinv * target;
        ThrustVec f0;
        const double mu_mn = max_scale(g, a, b);
        if (g.null_dim > 0 && mu_mn < 1.0 && mu_mn >= 0 && !g.facets.empty()) {
          // The zonotope's facets give the true largest scale at once; when the minimum-norm
          // pattern already reaches it (symmetric layouts), that is the answer, no LP.
          const double mu_f = std::min(1.0, facet_max_scale(g, -comp, target));
          if (mu_mn >= mu_f * (1 - 1e-12)) {
            fg = mu_mn * a + b;
            out.scale = std::min(out.scale, mu_mn);
            break;
          }
        }
        if (g.null_dim > 0 && mu_mn < 1.0 && feasible_start(g, b, f0)) {
          // Spare thrusters: the largest scale over the whole null space, not only along the
          // minimum-norm pattern; then the point nearest the minimum-norm one on the way there.
          double mu = lp_max_scale(g.lp, f0, target, 1.0, fg);
          if (mu > 1.0 - 1e-12) mu = 1.0;
          toward_feasible(g, mu * a + b, fg);
          out.scale = std::min(out.scale, mu);
          break;
        }
        const double mu = max_scale(g, a, b);
        if (mu < 0) {  // cannot even compensate: clip (reported through the status)
          fg = a + b;
          clamp_group(g, fg);
          out.scale = 0.0;
        } else {
          const double s = std::min(mu, 1.0);
          fg = s * a + b;
          out.scale = std::min(out.scale, s);
        }
        break;
      }
      case Strategy::kClip: {
        fg = g.pinv * target + b;
        clamp_group(g, fg);
        break;
      }
      case Strategy::kPrioritised: {
        // Levels in order, each as far as the room left allows. Each level's thrust pattern
        // makes only its own axes (B * pinv = I), so later passes can give an earlier level
        // room that a later level freed, without touching what the others got.
        fg = b;
        Small left = target;
        ThrustVec f0;
        if (g.null_dim > 0 && feasible_start(g, b, f0)) {
          // Spare thrusters: each level takes what the whole null space allows, with every other
          // axis held where it is (earlier levels at what they got, later ones so far).
          fg = f0;
          Small got = Small::Zero(na);
          ThrustVec fv;
          // A level is solved again only if another level moved since it was last solved.
          std::array<int, 6> solved_at;
          solved_at.fill(-1);
          int changes = 0;
          for (int pass = 0; pass < 4; ++pass) {
            bool progress = false;
            for (std::size_t li = 0; li < g.levels.size(); ++li) {
              const auto& level = g.levels[li];
              Small part = Small::Zero(na);
              for (int k : level) part(k) = left(k);
              if (part.cwiseAbs().maxCoeff() <= 0.0 || solved_at[li] == changes) continue;
              const ThrustVec v = g.pinv * part;
              double alpha;
              if (max_scale(g, v, fg) >= 1.0) {  // fits along the minimum-norm pattern
                alpha = 1.0;
                fv = fg + v;
              } else if (pass > 0 && !g.facets.empty() &&
                         facet_max_scale(g, got - comp, part) <= 1e-12) {
                // Solved again after other levels moved, and the facets say there is still no
                // room along this level (B fg = got - comp): no LP.
                alpha = 0.0;
              } else {
                alpha = lp_max_scale(g.lp, fg, part, 1.0, fv);
                if (alpha > 1.0 - 1e-12) alpha = 1.0;
              }
              solved_at[li] = changes;
              if (alpha > 1e-12) {
                ++changes;
                solved_at[li] = changes;
                fg = fv;
                for (int k : level) {
                  got(k) += alpha * part(k);
                  left(k) = alpha == 1.0 ? 0.0 : left(k) * (1.0 - alpha);
                }
                progress = true;
              }
            }
            if (!progress) break;
          }
          toward_feasible(g, g.pinv * got + b, fg);
        } else {
          if (max_scale(g, ThrustVec::Zero(b.size()), b) < 0) clamp_group(g, fg);
          for (int pass = 0; pass < 4; ++pass) {
            bool progress = false;
            for (const auto& level : g.levels) {
              Small part = Small::Zero(na);
              for (int k : level) part(k) = left(k);
              if (part.cwiseAbs().maxCoeff() <= 0.0) continue;
              const ThrustVec v = g.pinv * part;
              const double alpha = std::min(1.0, max_scale(g, v, fg));
              if (alpha > 1e-12) {
                fg += alpha * v;
                for (int k : level) left(k) *= 1.0 - alpha;
                progress = true;
              }
            }
            if (!progress) break;
          }
        }
        for (const auto& level : g.levels) {
          double l2 = 0, t2 = 0;
          for (int k : level) {
            l2 += left(k) * left(k);
            t2 += target(k) * target(k);
          }
          if (t2 > 0) out.scale = std::min(out.scale, 1.0 - std::sqrt(l2 / t2));
        }
        break;
      }
    }
    for (std::size_t k = 0; k < g.idx.size(); ++k) f(g.idx[k]) = fg(static_cast<Eigen::Index>(k));
  }
  finish(f, out);
  if (strategy_ == Strategy::kClip) {
    double num = 0, den = 0;
    for (int ax = 0; ax < 6; ++ax) {
      if (unactuated_[static_cast<std::size_t>(ax)]) continue;
      num += out.achieved(ax) * tau(ax);
      den += tau(ax) * tau(ax);
    }
    bool clipped = false;
    for (int i = 0; i < n_; ++i) clipped = clipped || out.saturated[static_cast<std::size_t>(i)];
    out.scale = den > 0 && clipped ? std::clamp(num / den, 0.0, 1.0) : 1.0;
  }
  return true;
}

bool Allocator::allocate_manual(const Wrench& stick, AllocationResult& out) const {
  if (!stick.allFinite() || stick.cwiseAbs().maxCoeff() > 1.0 + 1e-9) {
    neutral(out);
    return false;
  }
  out.demanded = stick;
  out.scale = 1.0;
  if (matrix_) {
    allocate_matrix(stick, out);
    out.manual = true;
    return true;
  }
  out.manual = true;
  out.target.setZero();
  ThrustVec f = ThrustVec::Zero(n_);
  for (const Group& g : groups_) {
    const auto na = static_cast<Eigen::Index>(g.axes.size());
    double m = 0;
    for (int ax : g.axes) m = std::max(m, std::abs(stick(ax)));
    const Small comp = g.rows * f;
    const ThrustVec b = -(g.pinv * comp);
    ThrustVec fg = b;
    if (m > 0) {
      Small d(na);  // direction: the stick on the square's edge, each axis at its own maximum
      for (Eigen::Index k = 0; k < na; ++k) {
        const int ax = g.axes[static_cast<std::size_t>(k)];
        d(k) = stick(ax) / m * axis_max(ax, stick(ax) >= 0 ? 1 : -1);
      }
      const ThrustVec a = g.pinv * d;
      double mu = max_scale(g, a, b);
      ThrustVec f0, fv;
      bool done = false;
      if (g.null_dim > 0 && mu >= 0 && !g.facets.empty()) {
        // Fast path: the largest along d from the zonotope's facets; the stick's fraction of it
        // along the minimum-norm pattern, when that fits.
        const double mu_f = facet_max_scale(g, -comp, d);
        if (std::isfinite(mu_f) && (m * mu_f) <= mu * (1 + 1e-12)) {
          mu = mu_f;
          fg = (m * mu) * a + b;
          clamp_group(g, fg);  // rounding only: m * mu_f is within the pattern's own reach
          done = true;
        }
      }
      if (done) {
      } else if (g.null_dim > 0 && feasible_start(g, b, f0)) {
        // Spare thrusters: the largest achievable along d over the whole null space (mu), then
        // the stick's fraction m of it: the minimum-norm point when it fits, else the nearest
        // to it on the way to m * (optimum) + (1 - m) * (start), which solves the same.
        mu = lp_max_scale(g.lp, f0, d, kInf, fv);
        if (!std::isfinite(mu)) mu = 0;
        fg = (m * mu) * a + b;
        ThrustVec mix = m * fv + (1.0 - m) * f0;
        toward_feasible(g, fg, mix);
        fg = mix;
      } else if (mu < 0) {
        fg = m * a + b;
        clamp_group(g, fg);
        out.scale = 0.0;
        mu = 0;
      } else {
        if (!std::isfinite(mu)) mu = 0;  // a == 0: nothing to do
        fg = (m * mu) * a + b;
      }
      for (Eigen::Index k = 0; k < na; ++k)
        out.target(g.axes[static_cast<std::size_t>(k)]) = m * mu * d(k);
    } else if (max_scale(g, ThrustVec::Zero(b.size()), b) < 0) {
      clamp_group(g, fg);
    }
    for (std::size_t k = 0; k < g.idx.size(); ++k) f(g.idx[k]) = fg(static_cast<Eigen::Index>(k));
  }
  finish(f, out);
  return true;
}

void Allocator::allocate_matrix(const Wrench& tau_norm, AllocationResult& out) const {
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> x(static_cast<Eigen::Index>(mix_axes_.size()));
  for (std::size_t j = 0; j < mix_axes_.size(); ++j)
    x(static_cast<Eigen::Index>(j)) = tau_norm(mix_axes_[j]);
  ThrustVec sv = mix_ * x;
  const bool commands = vehicle_.allocation.matrix_commands;
  const bool always = vehicle_.allocation.normalise_always;
  out.target.setZero();
  for (int ax : mix_axes_) out.target(ax) = tau_norm(ax) * full_scale_(ax);
  ThrustVec f(n_);
  if (!commands)
    for (int i = 0; i < n_; ++i)
      f(i) = sv(i) * vehicle_.thrusters[static_cast<std::size_t>(i)].max_forward_n;
  for (const Group& g : groups_) {
    if (strategy_ == Strategy::kClip) continue;  // finish() clips
    // Ratio-keeping normalisation: the factor that brings the group's largest value to its
    // limit (commands: magnitude 1; thrust fractions: the thruster's own forward / reverse
    // limit); applied when it is < 1, or always (normalise: always).
    double mu = kInf;
    if (commands) {
      double mx = 0;
      for (int i : g.idx) mx = std::max(mx, std::abs(sv(i)));
      if (mx > 0) mu = 1.0 / mx;
    } else {
      ThrustVec fg(static_cast<Eigen::Index>(g.idx.size()));
      for (std::size_t k = 0; k < g.idx.size(); ++k) fg(static_cast<Eigen::Index>(k)) = f(g.idx[k]);
      mu = max_scale(g, fg, ThrustVec::Zero(fg.size()));
    }
    if (mu < 1.0 || (always && std::isfinite(mu))) {
      for (int i : g.idx) {
        sv(i) *= mu;
        f(i) *= mu;
      }
      out.scale = std::min(out.scale, mu);  // a scale-up (always) leaves it at 1
    }
  }
  if (!commands) {
    finish(f, out);
    return;
  }
  // Commands are what the table says, sent as they are (within the commands that keep each
  // thruster inside its own thrust limits); the thrust is the curve's at them.
  for (int i = 0; i < n_; ++i) {
    const Thruster& t = vehicle_.thrusters[static_cast<std::size_t>(i)];
    sv(i) = std::clamp(sv(i), t.command_from_thrust(lo_[static_cast<std::size_t>(i)]),
                       t.command_from_thrust(hi_[static_cast<std::size_t>(i)]));
    f(i) = t.thrust_from_command(sv(i));
  }
  finish(f, out);
  for (int i = 0; i < n_; ++i) out.command[static_cast<std::size_t>(i)] = sv(i);
}

bool Allocator::finish(ThrustVec& f, AllocationResult& out) const {
  out.n = n_;
  out.axis_unactuated = unactuated_;
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double v = std::clamp(f(i), lo_[k], hi_[k]);
    f(i) = v;
    out.thrust[k] = v;
    out.saturated[k] = v >= hi_[k] * (1 - 1e-9) || v <= lo_[k] * (1 - 1e-9);
    out.command[k] = vehicle_.thrusters[k].command_from_thrust(v);
  }
  for (int i = n_; i < kMaxThrusters; ++i) {
    out.thrust[static_cast<std::size_t>(i)] = 0;
    out.command[static_cast<std::size_t>(i)] = 0;
    out.saturated[static_cast<std::size_t>(i)] = false;
  }
  out.achieved = b_ * f;
  for (int ax = 0; ax < 6; ++ax) {
    const auto a = static_cast<std::size_t>(ax);
    if (unactuated_[a]) {
      out.unallocated(ax) = 0;
      out.axis_reduced[a] = false;
    } else {
      out.unallocated(ax) = out.target(ax) - out.achieved(ax);
      out.axis_reduced[a] = std::abs(out.unallocated(ax)) > 1e-6 * (1.0 + std::abs(out.target(ax)));
    }
  }
  return true;
}

}  // namespace tiller
