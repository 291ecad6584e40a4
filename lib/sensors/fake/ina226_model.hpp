// A fake INA226 on i2c::FakeBus, for tests and benchmarks: the register pointer set by a
// write's first byte, 16-bit big-endian registers, MANUFACTURER_ID 0x5449 and DIE_ID 0x2260,
// configuration bit 15 resetting every register, and the data sheet's arithmetic: the shunt
// and bus registers hold what the test sets, Current = Shunt x CAL / 2048 and
// Power = Current x Bus / 20000 (both 0 while CAL is 0, as after power-on).
#pragma once

#include <array>
#include <cstdint>

#include "i2c/fake_bus.hpp"

namespace tiller::sensors::fake {

class Ina226Model : public i2c::FakeDevice {
 public:
  Ina226Model() { power_cycle(); }
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;

  std::uint16_t shunt = 0;  // raw shunt voltage register (2.5 uV/LSB, two's complement)
  std::uint16_t bus = 0;    // raw bus voltage register (1.25 mV/LSB)
  std::uint16_t manufacturer_id = 0x5449;

  void power_cycle();  // registers back to their power-on values (CAL = 0)
  std::uint16_t reg(std::uint8_t r) const;
  std::int64_t resets() const { return resets_; }

 private:
  std::uint16_t config_ = 0x4127, calibration_ = 0, mask_ = 0, alert_ = 0;
  std::uint8_t ptr_ = 0;
  std::int64_t resets_ = 0;
};

}  // namespace tiller::sensors::fake
