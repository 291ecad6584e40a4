// Models of the devices tiller-esc talks to, on the fake I2C bus (i2c/fake_bus.hpp), for
// tests, benchmarks and the dry-run backend.
//
// TgyEscModel: the BlueESC/tgy SIMPLE_I2C register map (see esc/tgy_backend.hpp): register
// pointer set by the first written byte, auto-increment on write and read; the throttle acts
// when its low byte (0x01) arrives; after power-up the ESC runs only once it has heard a zero
// throttle; with no throttle write for `stop_after_us` (4.5 s) it stops and needs a zero again;
// reading 0x02 returns and clears the commutation pulse count; 0x0A reads 0xAB.
// Pca9685Model: MODE1 (RESTART, EXTCLK, AI, SLEEP), MODE2, LEDn ON/OFF, ALL_LED, PRE_SCALE
// (writes ignored unless SLEEP = 1), power-up state asleep (MODE1 0x11, PRE_SCALE 0x1E), the
// oscillator runs 500 us after SLEEP is cleared; pulse_us(ch) is the width on the pin.
#pragma once

#include <array>
#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include "i2c/fake_bus.hpp"

namespace tiller::esc::fake {

class TgyEscModel : public i2c::FakeDevice {
 public:
  TgyEscModel();
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;

  // Model parameters.
  double max_rpm = 3800;  // at full throttle
  int poles = 14;
  TimeUs stop_after_us = 4'500'000;
  double volts = 16.0, amps = 0.5, temperature_c = 25.0;
  std::uint8_t identifier = 0xAB;

  // State.
  std::int16_t throttle() const { return throttle_; }  // last complete throttle written
  std::int16_t output() const { return output_; }      // what the motor does (0 when not armed)
  bool armed() const { return armed_; }
  std::int64_t throttle_writes() const { return throttle_writes_; }
  TimeUs last_throttle_time() const { return last_cmd_; }
  double pulses_pending() const { return pulses_; }
  void power_cycle();

 private:
  std::uint8_t read_reg(std::uint8_t r) const;
  std::uint8_t ptr_ = 0;
  std::uint8_t hi_ = 0;
  std::int16_t throttle_ = 0, output_ = 0;
  bool armed_ = false;
  bool ever_cmd_ = false;
  TimeUs last_cmd_ = 0, last_advance_ = 0;
  bool advanced_ = false;
  double pulses_ = 0;
  std::uint16_t latched_pulses_ = 0;
  std::int64_t throttle_writes_ = 0;
};

class Pca9685Model : public i2c::FakeDevice {
 public:
  explicit Pca9685Model(double oscillator_hz = 25e6);
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;

  double oscillator_hz;          // the chip's real internal oscillator
  double external_clock_hz = 0;  // what is on EXTCLK, if anything

  std::uint8_t reg(std::uint8_t r) const { return regs_[r]; }
  bool sleeping() const { return (regs_[0] & 0x10) != 0; }
  bool oscillator_running(TimeUs now) const;
  // Pulse width on channel ch (us), 0 when no pulses come out (asleep, not yet settled, off).
  double pulse_us(int ch, TimeUs now) const;
  int off_count(int ch) const;
  double pwm_hz() const;
  std::int64_t prescale_writes_ignored() const { return prescale_ignored_; }
  std::int64_t led_writes() const { return led_writes_; }
  void power_cycle();

 private:
  void write_reg(std::uint8_t r, std::uint8_t v, TimeUs now);
  std::array<std::uint8_t, 256> regs_{};
  std::uint8_t ptr_ = 0;
  TimeUs osc_ready_at_ = 0;
  std::int64_t prescale_ignored_ = 0;
  std::int64_t led_writes_ = 0;
};

}  // namespace tiller::esc::fake
