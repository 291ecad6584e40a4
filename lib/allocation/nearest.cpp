// The thrust nearest the minimum-norm one among the thrusts within limits that make a wrench
// (a least-distance problem in the null space, dual active set; no heap).
#include <algorithm>
#include <cmath>

#include "allocation/allocator.hpp"
#include "allocation/detail.hpp"

namespace tiller {

using namespace allocation_detail;

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
    if (c < n) return v[c] - (g.lp.hi[static_cast<std::size_t>(c)] + pad);
    return (g.lp.lo[static_cast<std::size_t>(c - n)] - pad) - v[c - n];
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
    for (int j = 0; j < n; ++j) {  // both limits of thruster j: constraints j and j + n
      const auto jj = static_cast<std::size_t>(j);
      const double inv = g.null_row_inv[jj];  // 0: fixed by the wrench alone, nothing to choose
      if (inv == 0.0) continue;
      const double up = (v[j] - (g.lp.hi[jj] + pad)) * inv;
      const double down = ((g.lp.lo[jj] - pad) - v[j]) * inv;
      if (up > worst && !active[j]) {
        worst = up;
        q = j;
      }
      if (down > worst && !active[j + n]) {
        worst = down;
        q = j + n;
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

}  // namespace tiller
