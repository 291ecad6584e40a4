#include "spi/fake_spi.hpp"

#include <algorithm>

namespace tiller::spi {

int FakeSpi::transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n) {
  ++transfers_;
  if (fault_count_ != 0 && fault_err_ != 0) {
    if (fault_count_ > 0) --fault_count_;
    if (rx) std::fill(rx, rx + n, 0);
    return fault_err_;
  }
  if (device_ == nullptr) {  // MISO floats high with nothing on it: reads 0xFF, no error
    if (rx) std::fill(rx, rx + n, 0xFF);
    return 0;
  }
  device_->on_transfer(tx, rx, n, now_);
  return 0;
}

void FakeSpi::set_time(TimeUs now) {
  if (now <= now_) return;
  now_ = now;
  if (device_) device_->advance(now_);
}

}  // namespace tiller::spi
