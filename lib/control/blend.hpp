// Bumpless hand-over between the velocity PID and station keeping: when a controller becomes
// the active source, its output is blended from the other controller's last wrench to its
// own over blend_s seconds, out = a * own + (1 - a) * from, a = (now - start) / blend_s in
// [0, 1]. Body FRD [X Y N], N and N m. Pure, allocation-free.
#pragma once

#include <algorithm>
#include <array>

#include "core/time.hpp"

namespace tiller::control {

class Blend {
 public:
  explicit Blend(double blend_s = 1.0) : blend_us_(from_seconds(blend_s)) {}
  // Starts a blend at `now` from `from` (the wrench in force before the hand-over).
  void start(TimeUs now, const std::array<double, 3>& from) {
    from_ = from;
    start_ = now;
    active_ = blend_us_ > 0;
  }
  void stop() { active_ = false; }
  // The blended output for the controller's own output `own`.
  std::array<double, 3> apply(TimeUs now, const std::array<double, 3>& own) {
    if (!active_) return own;
    const double a =
        std::clamp(static_cast<double>(now - start_) / static_cast<double>(blend_us_), 0.0, 1.0);
    if (a >= 1.0) active_ = false;
    return {a * own[0] + (1 - a) * from_[0], a * own[1] + (1 - a) * from_[1],
            a * own[2] + (1 - a) * from_[2]};
  }
  bool active() const { return active_; }

 private:
  TimeUs blend_us_;
  std::array<double, 3> from_{0, 0, 0};
  TimeUs start_ = 0;
  bool active_ = false;
};

}  // namespace tiller::control
