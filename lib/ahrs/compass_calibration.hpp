// Hard- and soft-iron calibration of a magnetometer from a recorded rotation: an ellipsoid fit.
//
// Model: the raw field r = S^-1 B + o, where B is the true field (its norm the same in every
// attitude), o the hard-iron offset (magnets and currents fixed to the vehicle) and S the soft-
// iron and scale matrix (iron that bends the field, unequal axis gains). The raw samples of a
// vehicle turned through many attitudes lie on the ellipsoid (r - o)^T M (r - o) = 1; the fit
// solves the quadric a x^2 + b y^2 + c z^2 + 2d xy + 2e xz + 2f yz + 2g x + 2h y + 2i z = 1 by
// linear least squares (Eigen's QR), o = -M^-1 [g h i], and S = radius * M'^(1/2) (symmetric
// square root, Eigen's SelfAdjointEigenSolver) with M' the shape normalised to 1 and `radius`
// the geometric mean of the semi-axes, so the corrected field B = S (r - o) keeps the measured
// strength. Quality: the residual (RMS of |S (r - o)| - radius, relative) and the coverage (the
// smallest over the largest spread of the corrected samples along the three principal axes: a
// rotation about one axis only gives ~0 and no fit).
// Used by tiller-navigator --calibrate-compass; the result is stored in the vehicle's navigator
// config (compass_calibration: {offset_ut: [3], matrix: [9 row-major], field_ut}).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace tiller::ahrs {

struct CompassCalibration {
  std::array<double, 3> offset{0, 0, 0};                    // o, raw units (uT)
  std::array<double, 9> matrix{1, 0, 0, 0, 1, 0, 0, 0, 1};  // S, row-major
  std::array<double, 3> apply(const std::array<double, 3>& raw) const;
};

struct FitResult {
  bool ok = false;
  std::string why;  // when not ok: what was wrong with the recording
  CompassCalibration cal;
  double radius = 0;             // field strength after correction (raw units)
  double relative_residual = 0;  // RMS(|B| - radius) / radius
  double coverage = 0;           // 0..1, smallest / largest principal spread
};

// At least 50 samples, coverage >= min_coverage, and a positive definite shape.
FitResult fit_ellipsoid(const std::vector<std::array<double, 3>>& raw, double min_coverage = 0.2);

}  // namespace tiller::ahrs
