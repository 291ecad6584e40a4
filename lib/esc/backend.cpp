#include "esc/backend.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

namespace tiller::esc {

EscBackend::EscBackend(std::vector<EscChannelParams> escs)
    : escs_(std::move(escs)), stats_(escs_.size()), telemetry_(escs_.size()) {}

void EscBackend::record(std::size_t i, int err, bool is_write) {
  EscStats& s = stats_[i];
  if (err == 0) {
    s.present = true;
    s.consecutive_errors = 0;
    return;
  }
  ++s.consecutive_errors;
  s.last_errno = err;
  if (is_write) {
    ++s.write_errors;
  } else {
    ++s.read_errors;
  }
}

std::int32_t throttle_from_normalized(double u) {
  if (!std::isfinite(u)) return 0;
  const double v = std::round(std::clamp(u, -1.0, 1.0) * 32767.0);
  return static_cast<std::int32_t>(v);
}

double normalized_from_throttle(std::int32_t throttle) {
  return throttle / 32767.0;
}

std::int32_t pulse_from_normalized(double u, const PulseRange& r) {
  if (!std::isfinite(u)) u = 0;
  u = std::clamp(u, -1.0, 1.0);
  const double p = u > 0 ? r.neutral_us + u * (r.max_us - r.neutral_us)
                         : r.neutral_us + u * (r.neutral_us - r.min_us);
  return static_cast<std::int32_t>(std::lround(p));
}

double normalized_from_pulse(std::int32_t pulse_us, const PulseRange& r) {
  const double d = pulse_us - r.neutral_us;
  if (d > 0) return r.max_us > r.neutral_us ? d / (r.max_us - r.neutral_us) : 0.0;
  return r.neutral_us > r.min_us ? d / (r.neutral_us - r.min_us) : 0.0;
}

}  // namespace tiller::esc
