#include "esc/pca9685_backend.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <tiller/esc_output_t.hpp>

namespace tiller::esc {

namespace pca9685 {
double clock_hz(const Pca9685Params& p) {
  return p.external_clock_hz > 0 ? p.external_clock_hz : p.oscillator_hz * p.oscillator_calibration;
}
int prescale(const Pca9685Params& p) {
  return static_cast<int>(std::lround(clock_hz(p) / (4096.0 * p.pwm_hz))) - 1;
}
double tick_us(const Pca9685Params& p) {
  return (prescale(p) + 1) * 1e6 / clock_hz(p);
}
}  // namespace pca9685

using namespace pca9685;

Pca9685Backend::Pca9685Backend(i2c::Transport& bus, Pca9685Params p,
                               std::vector<EscChannelParams> escs)
    : EscBackend(std::move(escs)),
      bus_(bus),
      p_(std::move(p)),
      addr_(static_cast<std::uint8_t>(p_.address)),
      tick_us_(tick_us(p_)) {
  label_ = "pca9685";
}

std::int8_t Pca9685Backend::unit() const {
  return esc_output_t::UNIT_PULSE_US;
}

std::int32_t Pca9685Backend::to_hardware(std::size_t i, double u) const {
  return pulse_from_normalized(u, escs_[i].pulse);
}

double Pca9685Backend::to_normalized(std::size_t i, std::int32_t hw) const {
  return normalized_from_pulse(hw, escs_[i].pulse);
}

int Pca9685Backend::counts(std::int32_t pulse_us) const {
  return std::clamp(static_cast<int>(std::lround(pulse_us / tick_us_)), 0, 4095);
}

Pca9685Backend::~Pca9685Backend() {
  if (oe_) oe_->set(1);  // outputs off
}

void Pca9685Backend::set_output_enable(std::unique_ptr<gpio::OutputLine> oe) {
  oe_ = std::move(oe);
  if (oe_) oe_->set(1);
}

int Pca9685Backend::reg(std::uint8_t r, std::uint8_t v) {
  const std::uint8_t buf[2] = {r, v};
  return bus_.write(addr_, buf, 2);
}

int Pca9685Backend::init_chip(std::uint8_t* prescale_read) {
  const std::uint8_t ext = p_.external_clock_hz > 0 ? kExtClk : 0;
  const auto pre = static_cast<std::uint8_t>(prescale(p_));
  if (oe_) oe_->set(1);                 // outputs off until a cycle of safe pulses went out
  int err = reg(kMode1, kSleep | kAi);  // oscillator off
  if (err == 0 && ext) err = reg(kMode1, kSleep | kAi | ext);  // EXTCLK: set while asleep
  if (err == 0) err = reg(kPreScale, pre);                     // only while asleep
  if (err == 0) err = reg(kMode2, p_.totem_pole ? kOutDrv : 0);
  if (err == 0) err = reg(kMode1, kAi | ext);  // wake
  if (err == 0) bus_.wait_us(500);             // oscillator settles
  if (err == 0) err = reg(kMode1, kRestart | kAi | ext);
  if (err == 0) {
    const std::uint8_t r = kPreScale;
    err = bus_.write_read(addr_, &r, 1, prescale_read, 1);
  }
  initialised_ = err == 0;
  return err;
}

StartReport Pca9685Backend::start(TimeUs now) {
  bus_.set_time(now);
  StartReport rep;
  const auto pre = static_cast<std::uint8_t>(prescale(p_));
  std::uint8_t back = 0;
  int err = bus_.claim(addr_);
  if (err == 0) err = init_chip(&back);
  next_check_ = now + kUsPerSecond;
  char line[240];
  if (err != 0) {
    std::snprintf(line, sizeof line, "no PCA9685 at 0x%02x on %s: %s (%zu ESC channels)\n", addr_,
                  bus_.name().c_str(), i2c::describe_errno(err).c_str(), size());
    rep.message = line;
    rep.all_present = false;
    for (std::size_t i = 0; i < size(); ++i) {
      record(i, err, true);
      stats_[i].present = false;
    }
    return rep;
  }
  if (back != pre) {
    std::snprintf(line, sizeof line,
                  "PCA9685 at 0x%02x on %s did not take the prescale: wrote 0x%02x, read 0x%02x "
                  "(another device at that address?)\n",
                  addr_, bus_.name().c_str(), pre, back);
    rep.message = line;
    rep.all_present = false;
  }
  // Neutral on every channel so the ESCs arm.
  std::vector<std::int32_t> neutral(size());
  for (std::size_t i = 0; i < size(); ++i) neutral[i] = to_hardware(i, 0.0);
  write(neutral.data(), now);
  if (!rep.all_present) {
    for (std::size_t i = 0; i < size(); ++i) stats_[i].present = false;
  }
  return rep;
}

bool Pca9685Backend::poll_telemetry(TimeUs now) {
  // Once a second: a board that was missing is initialised when it answers; a board that lost
  // power came back asleep (MODE1 SLEEP set, no pulses) and is initialised again.
  if (now < next_check_) return false;
  next_check_ = now + kUsPerSecond;
  std::uint8_t v = 0;
  if (initialised_) {
    const std::uint8_t r = kMode1;
    const int err = bus_.write_read(addr_, &r, 1, &v, 1);
    if (err != 0 || (v & kSleep) == 0) return false;
    ++reinits_;
  }
  std::uint8_t back = 0;
  init_chip(&back);
  return false;
}

void Pca9685Backend::write(const std::int32_t* hw, TimeUs now) {
  bus_.set_time(now);
  bool all_ok = true;
  for (std::size_t i = 0; i < size(); ++i) {
    const int off = counts(hw[i]);
    const std::uint8_t buf[5] = {static_cast<std::uint8_t>(kLed0OnL + 4 * escs_[i].address), 0x00,
                                 0x00, static_cast<std::uint8_t>(off & 0xFF),
                                 static_cast<std::uint8_t>((off >> 8) & 0x0F)};
    const int err = bus_.write(addr_, buf, sizeof buf);
    record(i, err, true);
    all_ok = all_ok && err == 0;
  }
  // Every channel has its pulse on an initialised chip: the outputs may be driven.
  if (oe_ && all_ok && initialised_ && oe_->level() != 0) oe_->set(0);
}

}  // namespace tiller::esc
