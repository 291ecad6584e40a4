// Wrench demand -> thrust: the fast path, the strategies per group (direction preserving,
// prioritised, clip), explicit tables, and finish() (limits, commands, achieved wrench).
#include "allocation/allocator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "allocation/detail.hpp"

namespace tiller {

using namespace allocation_detail;

void Allocator::set_supply_voltage(double volts) {
  for (auto& t : vehicle_.thrusters) t.curve.set_supply_voltage(volts);
}

bool Allocator::voltage_dependent() const {
  for (const auto& t : vehicle_.thrusters)
    if (t.curve.voltage_dependent()) return true;
  return false;
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
    // What earlier groups already do on these axes, and its minimum-norm compensation (both 0
    // for the first group: nothing is solved yet).
    const bool first = &g == &groups_.front();
    Small comp = Small::Zero(na);
    ThrustVec b = ThrustVec::Zero(static_cast<Eigen::Index>(g.idx.size()));
    if (!first) {
      comp = g.rows * f;
      b = -(g.pinv * comp);
    }
    ThrustVec fg;
    switch (strategy_) {
      case Strategy::kDirectionPreserving: {
        const ThrustVec a = g.pinv * target;
        ThrustVec f0;
        const double mu_mn = max_scale(g, a, b);
        if (g.null_dim > 0 && mu_mn < 1.0 && mu_mn >= 0 && !g.facets.empty()) {
          // The zonotope's facets give the true largest scale at once (the minimum-norm pattern
          // may already reach it: symmetric layouts); then the thrust nearest the minimum-norm
          // one that makes that wrench.
          const double mu = facet_max_scale(g, -comp, target, 1.0);
          fg = std::max(mu, mu_mn) * a + b;
          if (mu_mn < mu * (1 - 1e-12)) nearest_within_limits(g, fg);
          out.scale = std::min(out.scale, std::max(mu, mu_mn));
          break;
        }
        if (g.null_dim > 0 && mu_mn < 1.0 && feasible_start(g, b, f0)) {
          // Spare thrusters, too many facets to list: the largest scale over the whole null
          // space from the bounded simplex, then the thrust nearest the minimum-norm one.
          double mu = lp_max_scale(g.lp, f0, target, 1.0, fg);
          if (mu > 1.0 - 1e-12) mu = 1.0;
          fg = mu * a + b;
          nearest_within_limits(g, fg);
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
        // (max_scale(g, x, x) >= 0: x is within limits.)
        const bool facets =
            g.null_dim > 0 && !g.facets.empty() && (first || max_scale(g, b, b) >= 0);
        if (facets) {
          // Spare thrusters: each level takes what the whole null space allows, with every other
          // axis held where it is (earlier levels at what they got, later ones so far), from the
          // zonotope's facets; then the thrust nearest the minimum-norm one for what they got.
          Small got(na);
          prioritised_facets(g, target, comp, got, left);
          fg = g.pinv * got + b;
          nearest_within_limits(g, fg);
        } else if (g.null_dim > 0 && feasible_start(g, b, f0)) {
          // The same with too many facets to list: each level's room from the bounded simplex,
          // started from the previous level's thrust.
          fg = f0;
          Small got = Small::Zero(na);
          ThrustVec fv;
          std::array<int, 6> solved_at;  // a level is solved again only if another moved since
          solved_at.fill(-1);
          int changes = 0;
          for (int pass = 0; pass < 4; ++pass) {
            bool progress = false;
            for (std::size_t li = 0; li < g.levels.size(); ++li) {
              const auto& level = g.levels[li];
              Small part = Small::Zero(na);
              for (int k : level) part(k) = left(k);
              if (part.cwiseAbs().maxCoeff() <= 0.0 || solved_at[li] == changes) continue;
              double alpha = lp_max_scale(g.lp, fg, part, 1.0, fv);
              if (alpha > 1.0 - 1e-12) alpha = 1.0;
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
          fg = g.pinv * got + b;
          nearest_within_limits(g, fg);
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
