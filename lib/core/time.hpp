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

// The default bound on the offset between the clocks of two computers of one vehicle (a
// topside and a vehicle computer kept in step by chrony or NTP): how far a message's own utime,
// stamped by its sender's clock, may disagree with the receiver's clock. Processes take another
// value from --clock-offset-s / TILLER_CLOCK_OFFSET_S (launch file: clock_offset_s); see
// docs/safety.md, "Stalls and liveness".
inline constexpr TimeUs kDefaultClockOffsetUs = 250'000;

// How old an operator's event (an arm request, a mission START) may be by its utime and still
// be acted on (plus the clock offset bound): one that waited longer, in the queue of a stopped
// process say, is refused.
inline constexpr TimeUs kEventMaxAgeUs = 1'000'000;

// What a message's own time stamp says about it on arrival.
enum class Arrival : std::uint8_t {
  kAccepted,  // within the limits: it may refresh its input
  kStale,     // older than limit + clock offset by its utime: refused, refreshes nothing
  kFuture,    // newer than the receiver's clock + clock offset: refused (a sender's clock is off)
};

// A message received at `now` stamped `utime` by its sender's clock, for an input whose
// freshness limit is `limit`: kStale when now - utime > limit + clock_offset, kFuture when
// utime - now > clock_offset, else kAccepted. Exact at both edges (equal is accepted); safe for
// any utime from the wire (no overflow: only `now` is offset).
constexpr Arrival arrival_of(TimeUs now, TimeUs utime, TimeUs limit, TimeUs clock_offset) {
  if (utime < now - limit - clock_offset) return Arrival::kStale;
  if (utime > now + clock_offset) return Arrival::kFuture;
  return Arrival::kAccepted;
}

// Tracks an input: when it was last accepted (the receive time) and that message's own utime
// (the sender's clock), and says whether it is still fresh: both not older than the limit, the
// utime with the clock offset bound on top. A process that was stopped (SIGSTOP) and resumed
// receives its queued input with a receive time of now; the utime still says how old it is.
// Counts each transition from fresh to stale (what heartbeats report as "stale").
class Freshness {
 public:
  explicit Freshness(TimeUs limit_us = kUsPerSecond) : limit_(limit_us) {}
  void set_limit(TimeUs limit_us) { limit_ = limit_us; }
  TimeUs limit() const { return limit_; }
  // Marks an input received at `now`, stamped `utime` by its sender, if arrival_of() accepts it;
  // a refused one (kStale, kFuture) changes nothing. Nodes check first with Node::on_time,
  // which counts the refusals, so that a late message changes nothing else either.
  Arrival mark(TimeUs now, TimeUs utime, TimeUs clock_offset = kDefaultClockOffsetUs) {
    const Arrival a = arrival_of(now, utime, limit_, clock_offset);
    if (a != Arrival::kAccepted) return a;
    last_ = now;
    utime_ = utime;
    clock_offset_ = clock_offset;
    seen_ = true;
    was_fresh_ = true;
    return a;
  }
  // True if an input was accepted within the limit before `now` and its utime is within the
  // limit + clock offset before `now`. Updates the stale counter.
  bool fresh(TimeUs now) {
    const bool f = seen_ && now - last_ <= limit_ && now >= last_ - limit_ &&
                   utime_ >= now - limit_ - clock_offset_;
    if (was_fresh_ && !f) {
      ++stale_events_;
      was_fresh_ = false;
    }
    return f;
  }
  bool ever() const { return seen_; }
  TimeUs last() const { return last_; }
  TimeUs last_utime() const { return utime_; }
  std::int64_t stale_events() const { return stale_events_; }
  void reset() {
    seen_ = false;
    was_fresh_ = false;
  }

 private:
  TimeUs limit_;
  TimeUs last_ = 0;
  TimeUs utime_ = 0;
  TimeUs clock_offset_ = kDefaultClockOffsetUs;
  bool seen_ = false;
  bool was_fresh_ = false;
  std::int64_t stale_events_ = 0;
};

}  // namespace tiller
