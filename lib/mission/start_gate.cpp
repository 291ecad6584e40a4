#include "mission/start_gate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tiller::mission {

namespace {
constexpr std::int32_t kNeeded = int{odometry_t::VALID_POSITION} | int{odometry_t::VALID_VELOCITY} |
                                 int{odometry_t::VALID_ATTITUDE};
}

StartGate::StartGate(const StartGateParams& p)
    : p_(p),
      timeout_us_(from_seconds(p.odometry_timeout_s)),
      settle_us_(from_seconds(std::max(p.settle_s, 0.0))) {}

double StartGate::horizontal_std(const double* c) {
  // Eigenvalues of the symmetric 2x2 [[nn ne] [ne ee]] (row-major 6x6: nn 0, ne 1, ee 7).
  const double a = c[0], b = 0.5 * (c[1] + c[6]), d = c[7];
  const double mean = 0.5 * (a + d);
  const double dev = std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  return std::sqrt(std::max(mean + dev, 0.0));
}

void StartGate::on_odometry(const odometry_t& m, TimeUs now) {
  const bool gap = last_ >= 0 && now - last_ > timeout_us_;
  last_ = now;
  std_ = m.n_pose_cov == 36 ? horizontal_std(m.pose_covariance.data()) : 0.0;
  const char* bad = nullptr;
  if ((m.valid & kNeeded) != kNeeded) {
    bad = "the estimate is not valid (position, velocity and attitude)";
  } else if (m.valid & odometry_t::DEAD_RECKONING) {
    bad = "the estimate is dead reckoning (no position fix)";
  } else if (p_.max_position_std_m > 0 && std_ > p_.max_position_std_m) {
    std::snprintf(buf_.data(), buf_.size(), "position 1-sigma %.2f m > %.2f m", std_,
                  p_.max_position_std_m);
    bad = buf_.data();
  }
  reason_ = bad;
  if (bad != nullptr) {
    good_since_ = -1;
  } else if (good_since_ < 0 || gap) {
    good_since_ = now;
  }
}

bool StartGate::open(TimeUs now) const {
  if (!p_.enabled) return true;
  if (last_ < 0 || now - last_ > timeout_us_ || good_since_ < 0) return false;
  return now - good_since_ >= settle_us_;
}

const char* StartGate::why(TimeUs now) {
  if (open(now)) return "";
  if (last_ < 0) return "no odometry yet";
  if (now - last_ > timeout_us_) return "the odometry is stale";
  if (reason_ != nullptr) return reason_;
  std::snprintf(buf_.data(), buf_.size(), "settling: good for %.1f of %.1f s",
                to_seconds(now - good_since_), p_.settle_s);
  return buf_.data();
}

}  // namespace tiller::mission
