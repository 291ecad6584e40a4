// Helpers for the allocation tests: preset loading and seeded random wrenches.
#pragma once

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "allocation/allocator.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller::test {

// Every vehicle file in config/vehicles/ (by stem, sorted): a new vehicle is in every invariant
// test without editing this list (docs/adding-a-vehicle.md).
inline const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& e :
         std::filesystem::directory_iterator(std::string(TILLER_SOURCE_DIR) + "/config/vehicles")) {
      if (e.path().extension() == ".yaml") out.push_back(e.path().stem().string());
    }
    std::sort(out.begin(), out.end());
    return out;
  }();
  return names;
}

inline Vehicle preset(const std::string& name) {
  return load_vehicle_file(std::string(TILLER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml");
}

// Every preset the programs use: config/vehicles/*.yaml and the vehicle each config/mixer/*.yaml
// names (its `vehicle:` line, relative to the mixer file), each file once, sorted.
inline std::vector<std::string> preset_files() {
  namespace fs = std::filesystem;
  const fs::path src(TILLER_SOURCE_DIR);
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(src / "config/vehicles"))
    if (e.path().extension() == ".yaml") out.push_back(fs::canonical(e.path()).string());
  for (const auto& e : fs::directory_iterator(src / "config/mixer")) {
    if (e.path().extension() != ".yaml") continue;
    std::ifstream in(e.path());
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("vehicle:", 0) != 0) continue;
      std::string v = line.substr(8);
      v = v.substr(0, v.find('#'));
      v.erase(0, v.find_first_not_of(" \t\""));
      v.erase(v.find_last_not_of(" \t\"") + 1);
      const fs::path p = fs::path(v).is_absolute() ? fs::path(v) : e.path().parent_path() / v;
      out.push_back(fs::canonical(p).string());
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// A fully actuated 8-thruster ROV (BlueROV2 Heavy-like): seed 001's four vectored horizontal
// thrusters (45 degrees, 0.085 m below the CG) and four vertical ones at (+-0.12, +-0.22, 0) m,
// V0 and V3 pushing up, V1 and V2 mounted the other way up (pushing down), all with T200 limits
// (36.38 N forward, 28.43 N reverse): heave then uses forward thrust on two and reverse on the
// other two, so the vertical thrusters' spare direction is not symmetric. `group`: one name for all
// eight (one group owning all six axes, two spare directions) or "horizontal" / "vertical" as seed
// 001.
inline Vehicle rov8(bool one_group) {
  Vehicle v = preset("seed001_rov6");
  v.thrusters.erase(v.thrusters.begin() + 3);  // B
  v.thrusters.erase(v.thrusters.begin());      // F
  const double xs[4] = {0.12, 0.12, -0.12, -0.12}, ys[4] = {-0.22, 0.22, -0.22, 0.22};
  for (int k = 0; k < 4; ++k) {
    Thruster t = v.thrusters[0];
    // Not "V" + std::to_string(k): GCC 12 at -O3 inlines that operator+ and raises a false
    // -Werror=restrict inside std::string (GCC bug 105329 / 105651).
    t.name = std::to_string(k);
    t.name.insert(0, 1, 'V');
    t.position = {xs[k], ys[k], 0.0};
    t.direction = {0, 0, -1};
    if (k == 1 || k == 2) t.direction = {0, 0, 1};  // mounted the other way up
    t.group = "vertical";
    v.thrusters.push_back(t);
  }
  if (one_group)
    for (Thruster& t : v.thrusters) t.group = "all";
  v.name = one_group ? "rov8_one_group" : "rov8_two_groups";
  v.source_file.clear();
  return v;
}

// Random wrench on the actuated axes, each component scaled by that axis' largest value.
inline Wrench random_wrench(const Allocator& a, std::mt19937& rng, double size) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Wrench w = Wrench::Zero();
  for (int ax = 0; ax < 6; ++ax)
    if (!a.unactuated()[static_cast<std::size_t>(ax)])
      w(ax) = size * u(rng) * std::max(a.axis_max(ax, 1), a.axis_max(ax, -1));
  return w;
}

// Independent of the allocator: the largest mu >= 0 such that some thrust f within every
// thruster's own limits makes B f = mu * w on every actuated axis (other actuated axes 0), by
// vertex enumeration. With n thrusters and m actuated axes the optimum sits where n - m + 1
// thrusters are at a limit; for each such choice the m remaining unknowns (m - 1 thrusts and
// mu) follow from the m equations. Returns +inf if w is 0 on the actuated axes.
inline double brute_max_scale(const Vehicle& v, const std::array<bool, 6>& unactuated,
                              const Wrench& w) {
  std::vector<int> rows;
  for (int ax = 0; ax < 6; ++ax)
    if (!unactuated[static_cast<std::size_t>(ax)]) rows.push_back(ax);
  const int m = static_cast<int>(rows.size()), n = v.size(), fixed = n - m + 1;
  const Eigen::MatrixXd b_full = v.effectiveness();
  Eigen::MatrixXd b(m, n);
  Eigen::VectorXd wr(m);
  for (int r = 0; r < m; ++r) {
    b.row(r) = b_full.row(rows[static_cast<std::size_t>(r)]);
    wr(r) = w(rows[static_cast<std::size_t>(r)]);
  }
  if (wr.norm() == 0) return std::numeric_limits<double>::infinity();
  std::vector<double> lo(static_cast<std::size_t>(n)), hi(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    lo[static_cast<std::size_t>(i)] = v.thrusters[static_cast<std::size_t>(i)].thrust_min();
    hi[static_cast<std::size_t>(i)] = v.thrusters[static_cast<std::size_t>(i)].thrust_max();
  }
  double best = -1;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {  // which thrusters sit at a limit
    if (__builtin_popcount(mask) != fixed) continue;
    for (unsigned side = 0; side < (1u << fixed); ++side) {  // and at which one
      Eigen::MatrixXd a(m, m);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
      std::vector<int> free_idx;
      int bit = 0;
      for (int i = 0; i < n; ++i) {
        if (mask & (1u << i)) {
          const double fi = (side & (1u << bit++)) ? hi[static_cast<std::size_t>(i)]
                                                   : lo[static_cast<std::size_t>(i)];
          rhs -= b.col(i) * fi;
        } else {
          free_idx.push_back(i);
        }
      }
      for (int k = 0; k < m - 1; ++k) a.col(k) = b.col(free_idx[static_cast<std::size_t>(k)]);
      a.col(m - 1) = -wr;
      Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
      if (lu.rank() < m) continue;
      const Eigen::VectorXd sol = lu.solve(rhs);
      bool ok = sol(m - 1) >= 0;
      for (int k = 0; k < m - 1 && ok; ++k) {
        const auto i = static_cast<std::size_t>(free_idx[static_cast<std::size_t>(k)]);
        ok = sol(k) >= lo[i] - 1e-9 && sol(k) <= hi[i] + 1e-9;
      }
      if (ok) best = std::max(best, sol(m - 1));
    }
  }
  return best;
}

// A seed table in thruster commands: its commands are what the seed sends, not a solution for
// the demanded wrench (non-linear or asymmetric curves, `normalise: always`), so the wrench
// invariants do not apply; seeds_test.cpp checks these against the seeds' formulas instead.
inline bool command_table(const Vehicle& v) {
  return v.allocation.has_matrix() && v.allocation.matrix_commands;
}

// Same vehicle with another strategy (and the default priority X Y Z N M K when needed).
inline Vehicle with_strategy(Vehicle v, Strategy s) {
  v.allocation.strategy = s;
  if (s == Strategy::kPrioritised && v.allocation.priority.empty())
    v.allocation.priority = {{0}, {1}, {2}, {5}, {4}, {3}};
  return v;
}

}  // namespace tiller::test
