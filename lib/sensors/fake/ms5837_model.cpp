#include "sensors/fake/ms5837_model.hpp"

#include <cerrno>

namespace tiller::sensors::fake {

int Ms5837Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  if (n != 1) return EIO;
  cmd_ = d[0];
  if (cmd_ == ms5837::kCmdReset) {
    ++resets;
    converting_ = false;
    adc_ = 0;
  } else if ((cmd_ & 0xF0) == ms5837::kCmdConvertD1 || (cmd_ & 0xF0) == ms5837::kCmdConvertD2) {
    const auto osr = ms5837::osr_for(256 << ((cmd_ & 0x0F) / 2));
    if (osr.ratio == 0 || (cmd_ & 0x01)) return EIO;
    ++conversions;
    converting_ = true;
    pressure_ = (cmd_ & 0xF0) == ms5837::kCmdConvertD1;
    ready_at_ = now + osr.max_conversion_us;
    adc_ = 0;
  }
  return 0;
}

int Ms5837Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  if (cmd_ >= ms5837::kCmdPromRead && cmd_ <= ms5837::kCmdPromRead + 12 && n == 2) {
    const std::uint16_t w = prom_[static_cast<std::size_t>((cmd_ - ms5837::kCmdPromRead) / 2)];
    out[0] = static_cast<std::uint8_t>(w >> 8);
    out[1] = static_cast<std::uint8_t>(w);
    return 0;
  }
  if (cmd_ == ms5837::kCmdAdcRead && n == 3) {
    std::uint32_t v = 0;
    if (converting_ && now >= ready_at_) {
      v = pressure_ ? d1 : d2;
    } else {
      ++early_reads;
    }
    converting_ = false;
    out[0] = static_cast<std::uint8_t>(v >> 16);
    out[1] = static_cast<std::uint8_t>(v >> 8);
    out[2] = static_cast<std::uint8_t>(v);
    return 0;
  }
  return EIO;
}

}  // namespace tiller::sensors::fake
