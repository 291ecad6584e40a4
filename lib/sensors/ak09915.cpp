#include "sensors/ak09915.hpp"

#include <cerrno>

namespace tiller::sensors::ak09915 {

int continuous_mode(int rate_hz) {
  switch (rate_hz) {
    case 10:
      return 0x02;
    case 20:
      return 0x04;
    case 50:
      return 0x06;
    case 100:
      return 0x08;
    case 200:
      return 0x0C;
    default:
      return -1;
  }
}

Sample convert(const Burst& b) {
  Sample s;
  s.data_ready = (b[0] & kDrdy) != 0;
  s.overrun = (b[0] & kDor) != 0;
  s.overflow = (b[8] & kHofl) != 0;
  for (int i = 0; i < 3; ++i) {
    const auto raw = static_cast<std::int16_t>(b[1 + 2 * i] | (b[2 + 2 * i] << 8));
    s.field_ut[i] = raw * kMicroTeslaPerLsb;
  }
  return s;
}

int Device::start() {
  if (int e = write(kRegCntl3, kSoftReset)) return e;
  bus_.wait_us(kResetUs);
  std::uint8_t id[2] = {0, 0};
  if (int e = bus_.write_read(address_, &kRegWia1, 1, id, 2)) return e;
  wia_ = static_cast<std::uint16_t>((id[0] << 8) | id[1]);
  if (id[0] != kWia1 || id[1] != kWia2) return EPROTO;
  return write(kRegCntl2, mode_);
}

}  // namespace tiller::sensors::ak09915
