#include "ahrs/compass_calibration.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace tiller::ahrs {

std::array<double, 3> CompassCalibration::apply(const std::array<double, 3>& r) const {
  const double x = r[0] - offset[0], y = r[1] - offset[1], z = r[2] - offset[2];
  const auto& m = matrix;
  return {m[0] * x + m[1] * y + m[2] * z, m[3] * x + m[4] * y + m[5] * z,
          m[6] * x + m[7] * y + m[8] * z};
}

FitResult fit_ellipsoid(const std::vector<std::array<double, 3>>& raw, double min_coverage) {
  FitResult out;
  const auto n = static_cast<Eigen::Index>(raw.size());
  if (n < 50) {
    out.why = "only " + std::to_string(n) + " samples (at least 50: turn the vehicle for longer)";
    return out;
  }
  // Centre and scale the data first: the fit is then well conditioned whatever the units.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& r : raw) mean += Eigen::Vector3d(r[0], r[1], r[2]);
  mean /= static_cast<double>(n);
  double scale = 0;
  for (const auto& r : raw) scale += (Eigen::Vector3d(r[0], r[1], r[2]) - mean).norm();
  scale /= static_cast<double>(n);
  if (!(scale > 0)) {
    out.why = "every sample is the same (is the magnetometer reading?)";
    return out;
  }
  Eigen::MatrixXd a(n, 9);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto& r = raw[static_cast<std::size_t>(k)];
    const double x = (r[0] - mean[0]) / scale, y = (r[1] - mean[1]) / scale,
                 z = (r[2] - mean[2]) / scale;
    a.row(k) << x * x, y * y, z * z, 2 * x * y, 2 * x * z, 2 * y * z, 2 * x, 2 * y, 2 * z;
  }
  const Eigen::VectorXd p = a.colPivHouseholderQr().solve(Eigen::VectorXd::Ones(n));
  Eigen::Matrix3d m;
  m << p[0], p[3], p[4], p[3], p[1], p[5], p[4], p[5], p[2];
  const Eigen::Vector3d lin(p[6], p[7], p[8]);
  const Eigen::Vector3d centre = -m.ldlt().solve(lin);
  const double k = 1.0 + centre.dot(m * centre);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m / k);
  if (es.info() != Eigen::Success || es.eigenvalues().minCoeff() <= 0 || !(k > 0)) {
    out.why =
        "the samples do not lie on an ellipsoid: the rotation covered too few attitudes (roll "
        "and pitch the vehicle as well as turning it)";
    return out;
  }
  // Semi-axes 1/sqrt(lambda) (scaled units); radius = their geometric mean.
  const Eigen::Vector3d lam = es.eigenvalues();
  const double radius_scaled = std::cbrt(1.0 / std::sqrt(lam[0] * lam[1] * lam[2]));
  const Eigen::Matrix3d sqrt_m =
      es.eigenvectors() * lam.cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
  // In raw units: o = mean + scale * centre; S maps (r - o) / scale onto radius_scaled, i.e.
  // S = radius_scaled * sqrt_m (the 1/scale and the radius' scale cancel).
  const Eigen::Matrix3d s = radius_scaled * sqrt_m;
  const Eigen::Vector3d o = mean + scale * centre;
  for (int i = 0; i < 3; ++i) {
    out.cal.offset[static_cast<std::size_t>(i)] = o[i];
    for (int j = 0; j < 3; ++j) out.cal.matrix[static_cast<std::size_t>(3 * i + j)] = s(i, j);
  }
  out.radius = radius_scaled * scale;
  // Residual and coverage of the corrected samples.
  double sq = 0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& r : raw) {
    const auto b = out.cal.apply(r);
    const Eigen::Vector3d v(b[0], b[1], b[2]);
    const double d = v.norm() - out.radius;
    sq += d * d;
    cov += v * v.transpose();
  }
  out.relative_residual = std::sqrt(sq / static_cast<double>(n)) / out.radius;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> cs(cov / static_cast<double>(n));
  const Eigen::Vector3d spread = cs.eigenvalues().cwiseMax(0).cwiseSqrt();
  out.coverage = spread.maxCoeff() > 0 ? spread.minCoeff() / spread.maxCoeff() : 0;
  if (out.coverage < min_coverage) {
    out.why = "the rotation covered too few attitudes (coverage " +
              std::to_string(out.coverage).substr(0, 4) + " < " +
              std::to_string(min_coverage).substr(0, 4) +
              "): roll and pitch the vehicle as well as turning it";
    return out;
  }
  out.ok = true;
  return out;
}

}  // namespace tiller::ahrs
