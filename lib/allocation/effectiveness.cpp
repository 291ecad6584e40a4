// Allocator set-up: effectiveness matrix, actuated axes, groups and their solve order, pseudo-
// inverses, zonotope facets, largest value per axis; describe() and the unconstrained solution.
#include "allocation/allocator.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "allocation/detail.hpp"

namespace tiller {

using namespace allocation_detail;

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
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(bg, Eigen::ComputeFullV);
      g.null = svd.matrixV().rightCols(g.null_dim);
      double largest = 0;
      for (std::size_t k = 0; k < g.idx.size(); ++k) {
        g.null_row_norm[k] = g.null.row(static_cast<Eigen::Index>(k)).norm();
        g.null_row_inv[k] = g.null_row_norm[k] > 1e-12 ? 1.0 / g.null_row_norm[k] : 0.0;
        largest = std::max({largest, ghi[k], -glo[k]});
      }
      g.pad = 1e-12 * largest;
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
            // Generator subsets spanning the same hyperplane give the same facet: keep one.
            const bool seen = std::any_of(g.facets.begin(), g.facets.end(), [&](const auto& o) {
              for (int r = 0; r < m; ++r)
                if (std::abs(o[static_cast<std::size_t>(r)] - fct[static_cast<std::size_t>(r)]) >
                    1e-9)
                  return false;
              return true;
            });
            if (!seen) g.facets.push_back(fct);
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
    // The same facets by axis, for the hot path: component r of every normal in one array, and
    // per axis the facets whose normal has a positive / negative component along it.
    const auto nf = g.facets.size();
    g.facet_h.resize(nf);
    // facet_n rows padded with zeros to a multiple of 4 (prioritised_facets' updates).
    for (std::size_t r = 0; r < g.axes.size(); ++r)
      g.facet_n[r].assign((nf + 3) & ~std::size_t{3}, 0.0);
    for (std::size_t f = 0; f < nf; ++f) {
      g.facet_h[f] = g.facets[f][6];
      for (std::size_t r = 0; r < g.axes.size(); ++r) {
        const double c = g.facets[f][r];
        g.facet_n[r][f] = c;
        if (std::abs(c) <= 1e-12) continue;
        g.facet_by_axis[r][c > 0 ? 0 : 1].push_back(static_cast<int>(f));
        g.facet_inv_by_axis[r][c > 0 ? 0 : 1].push_back(1.0 / std::abs(c));
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

}  // namespace tiller
