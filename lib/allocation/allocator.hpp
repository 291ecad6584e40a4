// Thrust allocation: demanded wrench tau = [X Y Z K M N] (N, N m, body FRD, about the CG) ->
// thrust per thruster (N along its direction) -> thruster command in [-1, 1] through the
// inverse thrust curve. No LCM, no clock; nothing on the call path allocates.
//
// Built once per vehicle (everything that can be precomputed is):
//   * B, the 6 x n effectiveness matrix, from the geometry (Vehicle::effectiveness()).
//   * Actuated axes: greedy by rank in the order X, Y, Z, N, M, K. An axis whose row of B is a
//     combination of rows already taken is reported unactuated (a USV: Z, K, M; the 4-thruster
//     ROV also K and M, which its horizontal thrusters only produce as side effects). Nothing
//     singular is ever inverted.
//   * Independent thruster groups (the `group` of each thruster): each group owns the actuated
//     axes on which it adds rank, and gets its own pseudo-inverse over them. A group whose
//     thrust also acts on another group's axes (the ROV's horizontal thrusters pitch it because
//     they sit below the CG) is solved first, and the later group compensates what it actually
//     did. Two groups acting independently on one axis, or on each other's axes, are refused.
// Strategies (Vehicle::allocation.strategy), all within each thruster's own forward/reverse
// limits (reversal included):
//   direction_preserving  per group, the largest scale <= 1 of the group's demand that fits:
//                         the achieved wrench on the group's axes = scale * demand (seeds 001
//                         and 004: groups scaled independently, only when something exceeds);
//   prioritised           per group, axis levels in the configured order are added one by one,
//                         each as far as the remaining room allows: earlier levels are met
//                         exactly whenever they fit on their own;
//   Spare thrusters: when a group has more thrusters than owned axes (null space: X drive,
//   H drive, the 4-thruster ROV), "largest" is over every thrust that makes the wrench, not
//   only the minimum-norm (pseudo-inverse) pattern: the attainable set is a zonotope whose
//   facets (listed at load when there are at most kMaxFacets) give the room along any ray; a
//   group with more facets uses a small bounded simplex (lp_max_scale, fixed-size arrays,
//   <= 6 rows, <= 17 columns). The returned thrust is the minimum-norm one whenever that fits
//   (so the unsaturated path, and every group without spare thrusters, e.g. the Otter and
//   WAM-V, are the pseudo-inverse bit for bit), else the one nearest it among the thrusts
//   within limits that make the allocated wrench (nearest_within_limits: a least-distance
//   problem in the null space, dual active set): unique, so continuous in the demand. The
//   simplex gives axis_max() at load.
//   clip                  unconstrained solution clipped per thruster (for comparison only).
// Explicit-matrix vehicles (seed tables): s = M * tau_norm with tau_norm_j = tau_j /
// full_scale_j (full_scale: the wrench one unit of axis j gives, from the geometry). units:
// command -> s is the thruster command, sent as it is (seeds 001 and 004), thrust = curve(s);
// units: thrust_fraction -> thrust_i = s_i * max_forward_n_i. Ratio-keeping normalisation per
// group (the file's `group`s): normalise: above_one -> when some value is beyond its limit
// (command magnitude 1, or the thruster's own thrust limit) all of the group's are divided by
// the same factor; normalise: always -> the group's largest magnitude is made exactly 1 (a
// scale-up leaves `scale` at 1). The achieved wrench is still B * thrust from the geometry, so
// a table that does not match the hull shows in the status.
// Manual open-loop demand (allocate_manual): seed 000's two conditions, per group: the achieved
// wrench on the group's axes points along the stick vector J (each axis weighted by its own
// largest achievable value in that sign), and its size over the largest achievable in that
// direction (the true largest, null space included) equals |J| over the largest stick vector
// in that direction (= max_k |J_k|).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vehicle/vehicle.hpp"

namespace tiller {

using Wrench = Eigen::Matrix<double, 6, 1>;
using ThrustVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxThrusters, 1>;

// Largest |wrench component| accepted (wrench_t's documented range).
inline constexpr double kMaxWrenchComponent = 1e5;

struct AllocationResult {
  bool manual = false;  // true: `demanded` is a normalised stick vector
  Wrench demanded = Wrench::Zero();
  Wrench target = Wrench::Zero();         // what the allocator aimed at, N / N m
  Wrench achieved = Wrench::Zero();       // B * thrust (all six axes, side effects included)
  Wrench unallocated = Wrench::Zero();    // target - achieved on actuated axes, 0 elsewhere
  std::array<bool, 6> axis_reduced{};     // actuated axis that got less than demanded
  std::array<bool, 6> axis_unactuated{};  // the layout has no authority on this axis
  double scale = 1.0;  // 1 = met in full; < 1: fraction kept (smallest over groups / levels)
  int n = 0;
  std::array<double, kMaxThrusters> thrust{};   // N along each thruster's direction
  std::array<double, kMaxThrusters> command{};  // [-1, 1]
  std::array<bool, kMaxThrusters> saturated{};  // at its forward or reverse limit
};

class Allocator {
 public:
  // Throws std::invalid_argument naming the vehicle when groups are coupled both ways, etc.
  explicit Allocator(const Vehicle& vehicle);

  // Wrench in N / N m. Non-finite or |component| > kMaxWrenchComponent: neutral, false.
  bool allocate(const Wrench& tau, AllocationResult& out) const;
  // Normalised stick vector, each component in [-1, 1]. Invalid: neutral, false.
  bool allocate_manual(const Wrench& stick, AllocationResult& out) const;
  // Every command 0.
  void neutral(AllocationResult& out) const;
  // The supply (battery) voltage for thrusters whose curve depends on it (ThrustCurve's voltage
  // tables, `curve: t200`): thrust -> command from then on. Limits are unchanged. No allocation.
  void set_supply_voltage(double volts);
  bool voltage_dependent() const;

  int size() const { return n_; }
  Strategy strategy() const { return strategy_; }
  const char* strategy_name() const;
  bool uses_matrix() const { return matrix_; }
  const Eigen::MatrixXd& effectiveness() const { return b_full_; }
  const std::array<bool, 6>& unactuated() const { return unactuated_; }
  // Largest achievable wrench along +axis (sign > 0) or -axis alone, N or N m; 0 if unactuated.
  double axis_max(int axis, int sign) const { return axis_max_[sign > 0 ? 0 : 1][axis]; }
  // Unconstrained solution for tau (no limits): thrust = solve_unconstrained(tau).
  ThrustVec solve_unconstrained(const Wrench& tau) const;
  // Explicit-matrix vehicles: wrench per unit of each axis (tau_norm = tau / full_scale).
  const Wrench& full_scale() const { return full_scale_; }
  // Owned axes of each group, in solve order.
  std::vector<std::vector<int>> group_axes() const {
    std::vector<std::vector<int>> out;
    for (const auto& g : groups_) out.push_back(g.axes);
    return out;
  }
  // One line per group: name, thrusters, owned axes, order.
  std::string describe() const;
  const Vehicle& vehicle() const { return vehicle_; }

 private:
  using Small = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
  using RowsB = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxThrusters>;
  using PInv = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxThrusters, 6>;
  // A small bounded LP, set up when the vehicle is loaded: rows A (m x n, full row rank m <= 6,
  // n <= 16), an invertible starting set of m columns, its inverse, and the bounds.
  struct Lp {
    int m = 0, n = 0;
    std::array<int, 6> basis{};                                 // starting basis (columns of A)
    std::array<std::array<double, kMaxThrusters + 1>, 6> t0{};  // inverse(A[:, basis]) * A
    std::array<std::array<double, 6>, 6> binv0{};               // inverse(A[:, basis])
    std::array<double, kMaxThrusters> lo{}, hi{};
  };
  struct Group {
    std::string name;
    std::vector<int> idx;                  // thruster indices
    std::vector<int> axes;                 // owned axes
    RowsB rows;                            // B[axes, all thrusters]
    PInv pinv;                             // pinv(B[axes, idx]): idx.size() x axes.size()
    std::vector<std::vector<int>> levels;  // prioritised: positions into `axes`, by level
    int null_dim = 0;  // idx.size() - axes.size(): spare thrusters (0: the pseudo-inverse is all)
    Lp lp;             // over B[axes, idx], used only when null_dim > 0
    // Orthonormal basis of the null space of B[axes, idx] (idx.size() x null_dim), its rows'
    // norms, and the bound widening of nearest_within_limits (N).
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxThrusters, kMaxThrusters> null;
    std::array<double, kMaxThrusters> null_row_norm{};
    std::array<double, kMaxThrusters> null_row_inv{};  // 1 / null_row_norm, 0 for a fixed thruster
    double pad = 0;
    // The attainable set {B[axes, idx] f : lo <= f <= hi} is a zonotope; its facets (unit
    // normal n, support h: n . w <= h), when there are at most kMaxFacets, give the largest
    // scale along any ray without the LP (the LP then only finds the thrust).
    std::vector<std::array<double, 7>> facets;   // n[0..m-1], h at [6]; distinct
    std::array<std::vector<double>, 6> facet_n;  // facet_n[r][f] = facets[f][r], 0-padded to 4k
    std::vector<double> facet_h;                 // facet_h[f] = facets[f][6]
    std::array<std::array<std::vector<int>, 2>, 6> facet_by_axis;  // [r][0]: n_r > 0, [1]: < 0
    std::array<std::array<std::vector<double>, 2>, 6> facet_inv_by_axis;  // 1 / |n_r| of those
  };
  static constexpr std::size_t kMaxFacets = 128;
  // Largest mu in [0, cap] with c + mu d in group g's zonotope (c inside); cap if d is 0. Only
  // with facets.
  static double facet_max_scale(const Group& g, const Small& c, const Small& d, double cap);
  // Prioritised levels over the facets: target on the group's axes, comp what earlier groups do
  // there; got = what each axis gets (levels in order, passes), left = what it does not.
  void prioritised_facets(const Group& g, const Small& target, const Small& comp, Small& got,
                          Small& left) const;
  static Small group_wrench(const Group& g, const ThrustVec& fg);  // B[axes, idx] * fg

  // Max mu >= 0 with lo <= mu*a + b <= hi over group g; -1 if mu = 0 is infeasible;
  // +inf if unbounded.
  double max_scale(const Group& g, const ThrustVec& a, const ThrustVec& b) const;
  // Null space included: max mu in [0, cap] such that some f with lo <= f <= hi has
  // A f = A f0 + mu d (f0 feasible); f = an optimal point (a vertex). +inf if unbounded.
  static double lp_max_scale(const Lp& lp, const ThrustVec& f0, const Small& d, double cap,
                             ThrustVec& f);
  static Lp make_lp(const Eigen::MatrixXd& a, const std::array<double, kMaxThrusters>& lo,
                    const std::array<double, kMaxThrusters>& hi);
  // A feasible f for group g with B_g f = B_g b (b: the minimum-norm compensation); false if
  // there is none.
  bool feasible_start(const Group& g, const ThrustVec& b, ThrustVec& f0) const;
  // f in: the minimum-norm thrust for a wrench w (B_g f = w); out: the thrust nearest it among
  // those within limits that make w (unique; continuous in w). False if w is out of reach (f then
  // as near as the solver got). Allocates nothing.
  bool nearest_within_limits(const Group& g, ThrustVec& f) const;
  void clamp_group(const Group& g, ThrustVec& f) const;
  bool finish(ThrustVec& thrust, AllocationResult& out) const;
  void allocate_matrix(const Wrench& tau_norm, AllocationResult& out) const;

  Vehicle vehicle_;
  int n_ = 0;
  Strategy strategy_;
  bool matrix_ = false;
  Eigen::MatrixXd b_full_;
  Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxThrusters> b_;
  std::array<bool, 6> unactuated_{};
  std::vector<Group> groups_;  // in solve order
  std::array<double, kMaxThrusters> lo_{}, hi_{};
  std::array<std::array<double, 6>, 2> axis_max_{};
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxThrusters, 6> mix_;
  // The whole unconstrained cascade as one linear map (thrust = solve_ * tau): the fast path
  // when nothing saturates.
  Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxThrusters, 6> solve_;
  std::vector<int> mix_axes_;
  Wrench full_scale_ = Wrench::Ones();
};

}  // namespace tiller
