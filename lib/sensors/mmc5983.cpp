#include "sensors/mmc5983.hpp"

#include <cerrno>

namespace tiller::sensors::mmc5983 {

int continuous_freq(int rate_hz) {
  switch (rate_hz) {
    case 1:
      return 1;
    case 10:
      return 2;
    case 20:
      return 3;
    case 50:
      return 4;
    case 100:
      return 5;
    default:
      return -1;
  }
}

Sample convert(const Burst& b) {
  Sample s;
  s.data_ready = (b[8] & kMeasDone) != 0;
  for (int i = 0; i < 3; ++i) {
    const std::uint32_t raw = static_cast<std::uint32_t>(b[2 * i]) << 10 |
                              static_cast<std::uint32_t>(b[2 * i + 1]) << 2 |
                              ((b[6] >> (6 - 2 * i)) & 0x03u);
    s.field_ut[i] = (static_cast<double>(raw) - kNull) / kCountsPerGauss * 100.0;
  }
  return s;
}

int Device::start() {
  if (int e = write(kRegControl1, kSoftReset)) return e;
  bus_.wait_us(kResetUs);
  if (int e = bus_.write_read(address_, &kRegProductId, 1, &id_, 1)) return e;
  if (id_ != kProductId) return EPROTO;
  if (int e = write(kRegControl0, kAutoSetReset)) return e;
  if (int e = write(kRegControl1, 0x00)) return e;  // 100 Hz bandwidth
  return write(kRegControl2, static_cast<std::uint8_t>(kPeriodicSet | kContinuous | freq_));
}

}  // namespace tiller::sensors::mmc5983
