// Internal helpers shared by the allocator's source files (not part of the API).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <limits>
#include <vector>

namespace tiller::allocation_detail {

constexpr std::array<int, 6> kRankOrder = {0, 1, 2, 5, 4, 3};  // X Y Z N M K
constexpr double kInf = std::numeric_limits<double>::infinity();

inline int rank_of(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 0;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
  lu.setThreshold(1e-9);
  return static_cast<int>(lu.rank());
}

inline Eigen::MatrixXd rows_cols(const Eigen::MatrixXd& b, const std::vector<int>& rows,
                                 const std::vector<int>& cols) {
  Eigen::MatrixXd m(rows.size(), cols.size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < cols.size(); ++c)
      m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = b(rows[r], cols[c]);
  return m;
}

inline std::vector<int> all_cols(int n) {
  std::vector<int> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[static_cast<std::size_t>(i)] = i;
  return v;
}

}  // namespace tiller::allocation_detail
