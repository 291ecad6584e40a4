// A fake BNO055 on i2c::FakeBus, for tests and benchmarks: page 0 of the register map with
// auto-incrementing writes and burst reads, CHIP_ID 0xA0, and the operation-mode behaviour of
// the data sheet: the power-on state is CONFIGMODE (UNIT_SEL 0x80 as the register map table
// gives it); in CONFIGMODE the data registers read 0 and SYS_STATUS 0 (idle); other registers
// than OPR_MODE are written only in CONFIGMODE; a switch to a fusion mode takes 7 ms, after
// which SYS_STATUS reads 5 (fusion running) and the data registers hold what the test set.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/fake_bus.hpp"

namespace tiller::sensors::fake {

class Bno055Model : public i2c::FakeDevice {
 public:
  Bno055Model();
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;

  // The values the data registers hold while the fusion runs (raw LSB).
  void set_vector(std::uint8_t reg, std::int16_t x, std::int16_t y, std::int16_t z);
  void set_quaternion(std::int16_t w, std::int16_t x, std::int16_t y, std::int16_t z);
  void set_euler(std::int16_t heading, std::int16_t roll, std::int16_t pitch);
  std::uint8_t temp = 25;
  std::uint8_t calib_stat = 0xFF;
  std::uint8_t chip_id = 0xA0;
  // A system error to report (SYS_STATUS 1, SYS_ERR this) once the fusion would run.
  std::uint8_t sys_err = 0;

  void power_cycle();  // back to the power-on state (a brown-out)
  std::uint8_t reg(std::uint8_t r) const { return regs_[r]; }
  std::int64_t data_reads() const { return data_reads_; }

 private:
  std::uint8_t read_reg(std::uint8_t r, TimeUs now) const;
  std::array<std::uint8_t, 128> regs_{};
  std::array<std::uint8_t, 128> data_{};  // 0x08..0x33 while running
  std::uint8_t ptr_ = 0;
  TimeUs running_at_ = 0;
  std::int64_t data_reads_ = 0;
};

}  // namespace tiller::sensors::fake
