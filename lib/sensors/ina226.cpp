#include "sensors/ina226.hpp"

#include <cmath>

namespace tiller::sensors::ina226 {

std::uint16_t calibration(double current_lsb_a, double shunt_ohm) {
  if (!(current_lsb_a > 0) || !(shunt_ohm > 0)) return 0;
  // The tiny relative margin keeps an exact quotient (2560 for 1 mA and 2 mOhm) from
  // truncating to one less through rounding in the division.
  const double cal = std::floor(0.00512 / (current_lsb_a * shunt_ohm) * (1 + 1e-12));
  if (!(cal >= 1 && cal <= 32767)) return 0;
  return static_cast<std::uint16_t>(cal);
}

int averaging_code(int samples) {
  constexpr int kCounts[8] = {1, 4, 16, 64, 128, 256, 512, 1024};
  for (int i = 0; i < 8; ++i)
    if (kCounts[i] == samples) return i;
  return -1;
}

int conversion_time_code(int us) {
  constexpr int kTimes[8] = {140, 204, 332, 588, 1100, 2116, 4156, 8244};
  for (int i = 0; i < 8; ++i)
    if (kTimes[i] == us) return i;
  return -1;
}

std::uint16_t config_word(int avg_code, int vbus_ct_code, int vsh_ct_code) {
  return static_cast<std::uint16_t>(0x4000 | (avg_code & 7) << 9 | (vbus_ct_code & 7) << 6 |
                                    (vsh_ct_code & 7) << 3 | 7);
}

std::int64_t sample_period_us(int avg_samples, int vbus_ct_us, int vsh_ct_us) {
  return static_cast<std::int64_t>(avg_samples) * (vbus_ct_us + vsh_ct_us);
}

void Integrator::add(TimeUs t, double current_a, double power_w) {
  if (have_ && t > t_) {
    if (t - t_ <= max_gap_) {
      const double dt = static_cast<double>(t - t_) * 1e-6;
      charge_as_ += 0.5 * (i_ + current_a) * dt;
      energy_ws_ += 0.5 * (p_ + power_w) * dt;
    } else {
      ++gaps_;
    }
  }
  have_ = true;
  t_ = t;
  i_ = current_a;
  p_ = power_w;
}

}  // namespace tiller::sensors::ina226
