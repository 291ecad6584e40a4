// A fake MS5837 on i2c::FakeBus, for tests and benchmarks: answers reset, PROM reads
// (the words it is given) and conversions, whose ADC value (d1 / d2) is ready only after the
// OSR's maximum conversion time; an ADC read before that, or with no conversion started,
// returns 0 as the real device does.
#pragma once

#include <cstdint>

#include "i2c/fake_bus.hpp"
#include "sensors/ms5837.hpp"

namespace tiller::sensors::fake {

class Ms5837Model : public i2c::FakeDevice {
 public:
  explicit Ms5837Model(const ms5837::Prom& prom) : prom_(prom) {}
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;

  std::uint32_t d1 = 0, d2 = 0;  // raw values the next conversions give
  std::int64_t resets = 0, conversions = 0, early_reads = 0;

 private:
  ms5837::Prom prom_;
  std::uint8_t cmd_ = 0;
  bool converting_ = false, pressure_ = false;
  TimeUs ready_at_ = 0;
  std::uint32_t adc_ = 0;
};

}  // namespace tiller::sensors::fake
