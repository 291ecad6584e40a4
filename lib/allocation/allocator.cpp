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
  if (n_ < 1 || n_ > kMaxThrusters) throw std::invalid_argument(who + "1 to 16 thrusters");
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
        if (owner[static_cast<std::size_t>(ax)] >= 0)
          throw std::invalid_argument(
              who + "groups '" +
              groups[static_cast<std::size_t>(owner[static_cast<std::size_t>(ax)])].name +
              "' and '" + g.name + "' both act on axis " +
              kAxisNames[static_cast<std::size_t>(ax)] + "; put those thrusters in one group");
        owner[static_cast<std::size_t>(ax)] = static_cast<int>(gi);
        g.axes = trial;
      }
    }
  }
  for (int ax : actuated)
    if (owner[static_cast<std::size_t>(ax)] < 0)
      throw std::invalid_argument(who + "axis " +
                                  std::string(kAxisNames[static_cast<std::size_t>(ax)]) +
                                  " needs thrusters of several groups; merge those groups");
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
    if (!progress)
      throw std::invalid_argument(who +
                                  "thruster groups act on each other's axes both ways; "
                                  "merge them into one group");
  }
  for (Group& g : groups_) {
    g.rows = rows_cols(b_full_, g.axes, cols);
    if (!g.axes.empty()) {
      const Eigen::MatrixXd bg = rows_cols(b_full_, g.axes, g.idx);
      g.pinv = bg.completeOrthogonalDecomposition().pseudoInverse();
    } else {
      g.pinv.resize(static_cast<Eigen::Index>(g.idx.size()), 0);
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
  // Explicit mixing matrix.
  if (vehicle.allocation.has_matrix()) {
    matrix_ = true;
    mix_ = vehicle.allocation.matrix;
    mix_axes_ = vehicle.allocation.matrix_axes;
    full_scale_.setOnes();
    for (std::size_t j = 0; j < mix_axes_.size(); ++j) {
      ThrustVec f(n_);
      for (int i = 0; i < n_; ++i)
        f(i) = mix_(i, static_cast<Eigen::Index>(j)) *
               vehicle.thrusters[static_cast<std::size_t>(i)].max_forward_n;
      const double w = (b_ * f)(mix_axes_[j]);
      if (!(std::abs(w) > 1e-9))
        throw std::invalid_argument(
            who + "mixing matrix column " +
            std::string(kAxisNames[static_cast<std::size_t>(mix_axes_[j])]) +
            " produces nothing on that axis with this geometry");
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
        if (max_scale(g, ThrustVec::Zero(b.size()), b) < 0) clamp_group(g, fg);
        Small left = target;
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
      if (mu < 0) {
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
  const ThrustVec sv = mix_ * x;
  ThrustVec f(n_);
  for (int i = 0; i < n_; ++i)
    f(i) = sv(i) * vehicle_.thrusters[static_cast<std::size_t>(i)].max_forward_n;
  out.target.setZero();
  for (int ax : mix_axes_) out.target(ax) = tau_norm(ax) * full_scale_(ax);
  for (const Group& g : groups_) {
    if (strategy_ == Strategy::kClip) continue;  // finish() clips
    ThrustVec fg(static_cast<Eigen::Index>(g.idx.size()));
    for (std::size_t k = 0; k < g.idx.size(); ++k) fg(static_cast<Eigen::Index>(k)) = f(g.idx[k]);
    const double mu = max_scale(g, fg, ThrustVec::Zero(fg.size()));
    if (mu < 1.0) {  // ratio-keeping normalisation
      for (int i : g.idx) f(i) *= mu;
      out.scale = std::min(out.scale, mu);
    }
  }
  finish(f, out);
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
