// Manual open-loop demand: stick vector -> thrust (seed 000's two conditions, per group).
#include "allocation/allocator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "allocation/detail.hpp"

namespace tiller {

using namespace allocation_detail;

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
        // The largest along d from the zonotope's facets; the stick's fraction of it: the
        // minimum-norm thrust when it fits, else the thrust nearest it that makes the wrench.
        const double mu_f = facet_max_scale(g, -comp, d, kInf);
        if (std::isfinite(mu_f)) {
          const bool fits = (m * mu_f) <= mu * (1 + 1e-12);
          mu = mu_f;
          fg = (m * mu) * a + b;
          if (fits)
            clamp_group(g, fg);  // rounding only: m * mu_f is within the pattern's own reach
          else
            nearest_within_limits(g, fg);
          done = true;
        }
      }
      if (done) {
      } else if (g.null_dim > 0 && feasible_start(g, b, f0)) {
        // Spare thrusters, too many facets to list: the largest achievable along d over the
        // whole null space (mu) from the bounded simplex, then the stick's fraction m of it with
        // the thrust nearest the minimum-norm one.
        mu = lp_max_scale(g.lp, f0, d, kInf, fv);
        if (!std::isfinite(mu)) mu = 0;
        fg = (m * mu) * a + b;
        nearest_within_limits(g, fg);
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

}  // namespace tiller
