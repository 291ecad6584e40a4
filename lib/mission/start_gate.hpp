// mission::StartGate: is the vehicle's estimate good enough to start a mission from? A mission
// begun on an estimate that is still converging steers after the estimate's own correction
// (a 2.5 m CEP receiver's first fix is 2 to 3 m off, and tiller-nav takes about 15 s of fixes to
// average it down: docs/navigation.md). Like ArduPilot's "EKF not ready" / GPS accuracy pre-arm
// checks, tiller-mission waits (publishes no path, no arm request) until the gate is open.
//
// Open at `now` when TILLER_ODOMETRY (odometry_t, local NED) has been, continuously for
// `settle_s`:
//   * fresh: each sample within odometry_timeout_s of the one before, the last one within it of
//     `now`;
//   * valid: VALID_POSITION, VALID_VELOCITY and VALID_ATTITUDE set, DEAD_RECKONING clear;
//   * certain: the horizontal position's largest 1-sigma, sqrt of the larger eigenvalue of the
//     north-east block of pose_covariance (m), at most max_position_std_m. A message without a
//     covariance (n_pose_cov 0: the simulator's ground truth) is taken at its validity bits.
// Anything else restarts the settle time. why() says what is still missing, for the heartbeat.
// No clock, no allocation after construction: times are arguments (architecture's one rule).
#pragma once

#include <tiller/odometry_t.hpp>

#include <array>

#include "core/time.hpp"

namespace tiller::mission {

struct StartGateParams {
  bool enabled = false;             // false: the gate is always open (no odometry needed)
  double max_position_std_m = 0.5;  // m, largest horizontal 1-sigma; <= 0: not checked
  double settle_s = 0;              // s, how long the estimate must have been good
  double odometry_timeout_s = 0.5;  // s, a gap longer than this is stale odometry
};

class StartGate {
 public:
  explicit StartGate(const StartGateParams& p);

  // A checked odometry_t (core/message_checks.hpp) received at `now`.
  void on_odometry(const odometry_t& m, TimeUs now);
  bool open(TimeUs now) const;
  // What the gate waits for at `now` ("" when open), e.g. "position 1-sigma 1.23 m > 0.50 m".
  const char* why(TimeUs now);
  // The last sample's largest horizontal position 1-sigma, m (0 without a covariance, -1 before
  // the first sample).
  double position_std() const { return std_; }

  // The largest horizontal 1-sigma of a 6x6 row-major pose covariance [n e d roll pitch yaw].
  static double horizontal_std(const double* pose_covariance);

 private:
  StartGateParams p_;
  TimeUs timeout_us_, settle_us_;
  TimeUs good_since_ = -1;  // first sample of the current good run (-1: none)
  TimeUs last_ = -1;        // receive time of the last sample
  double std_ = -1;
  const char* reason_ = "no odometry yet";
  std::array<char, 96> buf_{};
};

}  // namespace tiller::mission
