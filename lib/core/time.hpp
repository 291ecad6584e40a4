// Time in Tiller: int64 microseconds (TimeUs), always passed in as an argument. Library code
// never reads a clock; only the live executor (lib/runtime/live.cpp) does.
#pragma once

#include <cstdint>

namespace tiller {

using TimeUs = std::int64_t;

constexpr TimeUs kUsPerSecond = 1'000'000;

constexpr double to_seconds(TimeUs t) {
  return static_cast<double>(t) * 1e-6;
}
constexpr TimeUs from_seconds(double s) {
  return static_cast<TimeUs>(s * 1e6 + (s >= 0 ? 0.5 : -0.5));
}
constexpr TimeUs from_hz(double hz) {
  return from_seconds(1.0 / hz);
}

// Tracks the time an input was last accepted and says whether it is still fresh.
// Counts each transition from fresh to stale (what heartbeats report as "stale").
class Freshness {
 public:
  explicit Freshness(TimeUs limit_us = kUsPerSecond) : limit_(limit_us) {}
  void set_limit(TimeUs limit_us) { limit_ = limit_us; }
  TimeUs limit() const { return limit_; }
  void mark(TimeUs now) {
    last_ = now;
    seen_ = true;
    was_fresh_ = true;
  }
  // True if an input was accepted within the limit before `now`. Updates the stale counter.
  bool fresh(TimeUs now) {
    const bool f = seen_ && now - last_ <= limit_ && now >= last_ - limit_;
    if (was_fresh_ && !f) {
      ++stale_events_;
      was_fresh_ = false;
    }
    return f;
  }
  bool ever() const { return seen_; }
  TimeUs last() const { return last_; }
  std::int64_t stale_events() const { return stale_events_; }
  void reset() {
    seen_ = false;
    was_fresh_ = false;
  }

 private:
  TimeUs limit_;
  TimeUs last_ = 0;
  bool seen_ = false;
  bool was_fresh_ = false;
  std::int64_t stale_events_ = 0;
};

}  // namespace tiller
