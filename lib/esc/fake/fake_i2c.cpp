#include "esc/fake/fake_i2c.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>

namespace tiller::esc::fake {

// ------------------------------------------------------------------------------ TgyEscModel

TgyEscModel::TgyEscModel() = default;

void TgyEscModel::power_cycle() {
  ptr_ = 0;
  hi_ = 0;
  throttle_ = output_ = 0;
  armed_ = false;
  ever_cmd_ = false;
  pulses_ = 0;
}

void TgyEscModel::advance(TimeUs now) {
  if (!advanced_) {
    advanced_ = true;
    last_advance_ = now;
  }
  if (now > last_advance_) {
    const double rev_per_s = std::abs(output_) / 32767.0 * max_rpm / 60.0;
    pulses_ += rev_per_s * poles * to_seconds(now - last_advance_);
    last_advance_ = now;
  }
  if (armed_ && ever_cmd_ && now - last_cmd_ > stop_after_us) {
    // No command for 4-5 s: the motor stops, and it needs a zero throttle before running again.
    output_ = 0;
    armed_ = false;
  }
}

int TgyEscModel::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  advance(now);
  if (n == 0) return 0;
  ptr_ = d[0];
  for (std::size_t k = 1; k < n; ++k, ++ptr_) {
    if (ptr_ == 0x00) {
      hi_ = d[k];
    } else if (ptr_ == 0x01) {
      // The low byte completes the throttle: the ESC acts now.
      throttle_ = static_cast<std::int16_t>(static_cast<std::uint16_t>((hi_ << 8) | d[k]));
      ++throttle_writes_;
      last_cmd_ = now;
      ever_cmd_ = true;
      if (!armed_) {
        if (throttle_ == 0) armed_ = true;
        output_ = 0;
      } else {
        output_ = throttle_;
      }
    }
    // 0x02.. are read-only: writes are ignored.
  }
  return 0;
}

std::uint8_t TgyEscModel::read_reg(std::uint8_t r) const {
  auto hi = [](std::uint16_t v) { return static_cast<std::uint8_t>(v >> 8); };
  auto lo = [](std::uint16_t v) { return static_cast<std::uint8_t>(v & 0xFF); };
  const auto v_raw =
      static_cast<std::uint16_t>(std::clamp(volts / (5.0 * 6.45) * 65536.0, 0.0, 65535.0));
  const auto c_raw = static_cast<std::uint16_t>(
      std::clamp(32767.0 + amps / (5.0 * 14.706) * 65535.0, 0.0, 65535.0));
  // NTC 10 kOhm, B 3900 at temperature_c; raw = 65535 / (1 + 3300 / R).
  const double r_ntc =
      10000.0 * std::exp(3900.0 * (1.0 / (temperature_c + 273.15) - 1.0 / (25.0 + 273.15)));
  const auto t_raw = static_cast<std::uint16_t>(std::lround(65535.0 / (1.0 + 3300.0 / r_ntc)));
  switch (r) {
    case 0x02:
      return hi(latched_pulses_);
    case 0x03:
      return lo(latched_pulses_);
    case 0x04:
      return hi(v_raw);
    case 0x05:
      return lo(v_raw);
    case 0x06:
      return hi(t_raw);
    case 0x07:
      return lo(t_raw);
    case 0x08:
      return hi(c_raw);
    case 0x09:
      return lo(c_raw);
    case 0x0A:
      return identifier;
    default:
      return 0;
  }
}

int TgyEscModel::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  advance(now);
  for (std::size_t k = 0; k < n; ++k, ++ptr_) {
    if (ptr_ == 0x02) {
      // Reading the pulse count latches and clears it.
      const double whole = std::min(std::floor(pulses_), 65535.0);
      latched_pulses_ = static_cast<std::uint16_t>(whole);
      pulses_ -= whole;
    }
    out[k] = read_reg(ptr_);
  }
  return 0;
}

// ----------------------------------------------------------------------------- Pca9685Model

Pca9685Model::Pca9685Model(double osc_hz) : oscillator_hz(osc_hz) {
  power_cycle();
}

void Pca9685Model::power_cycle() {
  regs_.fill(0);
  regs_[0x00] = 0x11;                                               // SLEEP | ALLCALL
  regs_[0x01] = 0x04;                                               // OUTDRV
  for (int ch = 0; ch < 16; ++ch) regs_[0x06 + 4 * ch + 3] = 0x10;  // full OFF
  regs_[0xFE] = 0x1E;
  ptr_ = 0;
  osc_ready_at_ = 0;
}

void Pca9685Model::write_reg(std::uint8_t r, std::uint8_t v, TimeUs now) {
  if (r == 0x00) {
    const std::uint8_t old = regs_[0];
    const bool was_sleeping = (old & 0x10) != 0;
    const bool sleep = (v & 0x10) != 0;
    std::uint8_t restart = (v & 0x80) ? 0 : (old & 0x80);  // writing 1 clears RESTART
    if (!was_sleeping && sleep) restart = 0x80;            // PWM was running: can restart
    // EXTCLK is sticky and can only be set while asleep.
    const std::uint8_t ext = (old & 0x40) | ((was_sleeping && (v & 0x40)) ? 0x40 : 0);
    regs_[0] = static_cast<std::uint8_t>((v & 0x3F) | ext | restart);
    if (was_sleeping && !sleep) osc_ready_at_ = now + 500;
    return;
  }
  if (r == 0xFE) {
    if (!sleeping()) {
      ++prescale_ignored_;
      return;
    }
    regs_[0xFE] = std::max<std::uint8_t>(v, 3);
    return;
  }
  if (r >= 0xFA && r <= 0xFD) {
    for (int ch = 0; ch < 16; ++ch) regs_[0x06 + 4 * ch + (r - 0xFA)] = v;
    regs_[r] = v;
    return;
  }
  if (r >= 0x06 && r <= 0x45) ++led_writes_;
  regs_[r] = v;
}

int Pca9685Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  if (n == 0) return 0;
  ptr_ = d[0];
  for (std::size_t k = 1; k < n; ++k) {
    write_reg(ptr_, d[k], now);
    if (regs_[0] & 0x20) ++ptr_;  // AI
  }
  return 0;
}

int Pca9685Model::on_read(std::uint8_t* out, std::size_t n, TimeUs) {
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = regs_[ptr_];
    if (regs_[0] & 0x20) ++ptr_;
  }
  return 0;
}

bool Pca9685Model::oscillator_running(TimeUs now) const {
  return !sleeping() && now >= osc_ready_at_;
}

double Pca9685Model::pwm_hz() const {
  const double clk = (regs_[0] & 0x40) ? external_clock_hz : oscillator_hz;
  return clk / (4096.0 * (regs_[0xFE] + 1));
}

int Pca9685Model::off_count(int ch) const {
  const int b = 0x06 + 4 * ch;
  return ((regs_[b + 3] & 0x0F) << 8) | regs_[b + 2];
}

double Pca9685Model::pulse_us(int ch, TimeUs now) const {
  if (!oscillator_running(now)) return 0;
  const int b = 0x06 + 4 * ch;
  const bool full_on = (regs_[b + 1] & 0x10) != 0;
  const bool full_off = (regs_[b + 3] & 0x10) != 0;
  const double period_us = 1e6 / pwm_hz();
  if (full_off) return 0;
  if (full_on) return period_us;
  const int on = ((regs_[b + 1] & 0x0F) << 8) | regs_[b];
  const int counts = (off_count(ch) - on) & 0xFFF;
  return counts * period_us / 4096.0;
}

}  // namespace tiller::esc::fake
