// PWM ESCs through a PCA9685 16-channel PWM board on I2C (seed 001's duty-cycle board).
//
// Registers (NXP PCA9685 datasheet; docs/escs-and-wiring.md): MODE1 0x00 (RESTART 0x80, EXTCLK
// 0x40, AI 0x20, SLEEP 0x10), MODE2 0x01 (OUTDRV 0x04), LEDn_ON_L = 0x06 + 4n (ON_L, ON_H, OFF_L,
// OFF_H), PRE_SCALE 0xFE (writable only while SLEEP = 1). Power-up state: asleep, no pulses.
// Start-up: MODE1 <- SLEEP|AI
// (+EXTCLK, set while asleep), PRE_SCALE <- round(f_clk / (4096 f_pwm)) - 1, MODE2 <- OUTDRV (totem
// pole) or 0, MODE1 <- AI (wake), wait 500 us, MODE1 <- RESTART|AI, read MODE1 and PRE_SCALE back,
// then every channel to its neutral pulse. Each cycle: one 5-byte auto-increment write per channel
// [LEDn_ON_L, 0, 0, OFF_L, OFF_H], OFF = round(pulse_us / tick_us), tick_us = (prescale + 1) /
// f_clk. f_clk = oscillator_hz * oscillator_calibration (the internal 25 MHz oscillator is off
// by a few percent), or the external clock when one is configured.
// Output enable (the Navigator's PWM_OE, GPIO 26 on the Pi; PCA9685 /OE is active low: low =
// outputs driven, high = every output off): with an OE line the backend drives it high from the
// start and at every (re)initialisation of the chip, and low only after a whole cycle of pulses
// went out to an initialised chip (neutral while disarmed: the ESC node's safe output), so the
// ESCs see no pulse until tiller-esc runs and writes its safe values; the destructor (and the
// exit: the board's pull-up) drives it high again.
#pragma once

#include <memory>
#include <string>

#include "esc/backend.hpp"
#include "gpio/output.hpp"
#include "i2c/transport.hpp"

namespace tiller::esc {

struct Pca9685Params {
  std::string bus = "/dev/i2c-1";
  int address = 0x40;
  double pwm_hz = 50;
  double oscillator_hz = 25e6;          // nominal internal oscillator
  double oscillator_calibration = 1.0;  // measured / nominal
  double external_clock_hz = 0;         // > 0: EXTCLK input at this frequency
  bool totem_pole = true;               // MODE2 OUTDRV
  PulseRange pulse;                     // default for every channel
  std::string oe_chip = "gpiochip0";    // output-enable line's GPIO chip
  int oe_line = -1;                     // its offset; -1: no OE line
};

namespace pca9685 {
constexpr std::uint8_t kMode1 = 0x00, kMode2 = 0x01, kLed0OnL = 0x06, kAllLedOnL = 0xFA,
                       kPreScale = 0xFE;
constexpr std::uint8_t kRestart = 0x80, kExtClk = 0x40, kAi = 0x20, kSleep = 0x10, kOutDrv = 0x04;
// Clock feeding the prescaler, Hz.
double clock_hz(const Pca9685Params& p);
// round(f_clk / (4096 f_pwm)) - 1; the loader checks 3..255.
int prescale(const Pca9685Params& p);
// Length of one of the 4096 counts, us.
double tick_us(const Pca9685Params& p);
}  // namespace pca9685

class Pca9685Backend : public EscBackend {
 public:
  Pca9685Backend(i2c::Transport& bus, Pca9685Params p, std::vector<EscChannelParams> escs);
  ~Pca9685Backend() override;
  // The output-enable line (requested high: outputs off). Without one, outputs follow the chip.
  void set_output_enable(std::unique_ptr<gpio::OutputLine> oe);
  // True while OE is driven low (outputs on); always true without an OE line.
  bool outputs_enabled() const { return !oe_ || oe_->level() == 0; }
  std::int8_t unit() const override;
  std::string bus() const override { return bus_.name(); }
  StartReport start(TimeUs now) override;
  std::int32_t to_hardware(std::size_t i, double u) const override;
  double to_normalized(std::size_t i, std::int32_t hw) const override;
  void write(const std::int32_t* hw, TimeUs now) override;
  // Once a second: initialises a board that appeared late, or that lost power (found asleep).
  bool poll_telemetry(TimeUs now) override;
  // OFF count for a pulse width.
  int counts(std::int32_t pulse_us) const;
  bool initialised() const { return initialised_; }
  std::int64_t reinits() const { return reinits_; }

 private:
  int reg(std::uint8_t r, std::uint8_t v);
  int init_chip(std::uint8_t* prescale_read);
  i2c::Transport& bus_;
  Pca9685Params p_;
  std::uint8_t addr_;
  double tick_us_;
  bool initialised_ = false;
  TimeUs next_check_ = 0;
  std::int64_t reinits_ = 0;
  std::unique_ptr<gpio::OutputLine> oe_;
};

}  // namespace tiller::esc
