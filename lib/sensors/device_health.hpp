// How a sensor node judges the device it reads over a bus (tiller-pressure, tiller-imu and
// tiller-power share it, so they say the same things the same way):
// - a failed transfer is tried once more at once (`retry_once`, counted "bus.retries");
// - a tick whose transfer still fails is a failure (`failed`); `fault_after` of them in a row, or
//   a failed set-up, and the device is down (`down`): FAULT, the status naming the bus, the
//   address and the reason, and a new set-up no sooner than `retry_period` later (`may_try`);
// - any failure in the last second (`failed_recently`): DEGRADED.
// Time is the node's tick time (us). No allocation except when `down` builds its text.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "core/time.hpp"
#include "i2c/transport.hpp"

namespace tiller::sensors {

// "0x76": an address or register value for a status text.
inline std::string hex(unsigned v, int digits = 2) {
  char b[12];
  std::snprintf(b, sizeof b, "0x%0*x", digits, v);
  return b;
}

// op() returns 0 or an errno; a non-zero result is counted in `retries` and op() runs again.
// `no_retry(err)` says which results are not worth a second try (default: none).
template <class Op, class NoRetry>
int retry_once(std::int64_t& retries, Op&& op, NoRetry&& no_retry) {
  const int err = op();
  if (err == 0 || no_retry(err)) return err;
  ++retries;
  return op();
}
template <class Op>
int retry_once(std::int64_t& retries, Op&& op) {
  return retry_once(retries, op, [](int) { return false; });
}

class DeviceHealth {
 public:
  // where: "ms5837-30ba on /dev/i2c-1 at 0x76"; retry_period > 0; fault_after >= 1.
  DeviceHealth(std::string where, TimeUs retry_period, int fault_after)
      : where_(std::move(where)), retry_period_(retry_period), fault_after_(fault_after) {}

  const std::string& where() const { return where_; }

  // A tick's transfer failed after its retry: true when that makes `fault_after` in a row.
  bool failed(TimeUs now) {
    last_failure_ = now;
    return ++consecutive_ >= fault_after_;
  }
  // Something went wrong that is not a failed transfer (the chip reset itself): DEGRADED for a
  // second, the count of failures in a row unchanged.
  void glitch(TimeUs now) { last_failure_ = now; }
  void succeeded() { consecutive_ = 0; }
  int consecutive() const { return consecutive_; }
  bool failed_recently(TimeUs now) const {
    return last_failure_ != INT64_MIN && now - last_failure_ < kUsPerSecond;
  }

  // The device is down: returns the FAULT status "<where>: <why>[: <errno text>]; retrying every
  // N ms" and allows the next set-up at now + retry_period. err 0: no errno to name.
  const std::string& down(TimeUs now, int err, std::string_view why) {
    next_try_ = now + retry_period_;
    consecutive_ = 0;
    status_ = where_ + ": ";
    status_ += why;
    if (err != 0) status_ += ": " + i2c::describe_errno(err);
    status_ += "; retrying every " + std::to_string(retry_period_ / 1000) + " ms";
    return status_;
  }
  bool may_try(TimeUs now) const { return now >= next_try_; }
  TimeUs next_try() const { return next_try_; }

 private:
  std::string where_;
  TimeUs retry_period_;
  int fault_after_;
  int consecutive_ = 0;
  TimeUs last_failure_ = INT64_MIN;
  TimeUs next_try_ = INT64_MIN;
  std::string status_;
};

}  // namespace tiller::sensors
