#include "esc/tgy_backend.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>

#include <tiller/esc_output_t.hpp>

namespace tiller::esc {

TgyTelemetryRaw decode_tgy_telemetry(const std::uint8_t (&b)[9]) {
  auto be16 = [&](int k) { return static_cast<std::uint16_t>((b[k] << 8) | b[k + 1]); };
  TgyTelemetryRaw r;
  r.pulses = be16(0);
  r.voltage = be16(2);
  r.temperature = be16(4);
  r.current = be16(6);
  r.identifier = b[8];
  return r;
}

double tgy_voltage(std::uint16_t raw) {
  return raw / 65536.0 * 5.0 * 6.45;
}

double tgy_current(std::uint16_t raw) {
  return (raw - 32767.0) / 65535.0 * 5.0 * 14.706;
}

double tgy_temperature(std::uint16_t raw) {
  // NTC 10 kOhm at 25 degC, B = 3900, 3.3 kOhm series resistor (BlueESC); beta equation.
  if (raw == 0 || raw == 65535) return std::nan("");
  const double r_ntc = 3300.0 / (65535.0 / raw - 1.0);
  const double inv_t = std::log(r_ntc / 10000.0) / 3900.0 + 1.0 / (25.0 + 273.15);
  return 1.0 / inv_t - 273.15;
}

TgyBackend::TgyBackend(i2c::Transport& bus, TgyParams p, std::vector<EscChannelParams> escs)
    : EscBackend(std::move(escs)),
      bus_(bus),
      p_(std::move(p)),
      last_hw_(size(), 0),
      last_read_(size(), 0),
      read_before_(size(), 0) {
  label_ = "i2c_tgy";
}

std::int8_t TgyBackend::unit() const {
  return esc_output_t::UNIT_THROTTLE_INT16;
}

std::int32_t TgyBackend::to_hardware(std::size_t, double u) const {
  return throttle_from_normalized(u);
}

double TgyBackend::to_normalized(std::size_t, std::int32_t hw) const {
  return normalized_from_throttle(hw);
}

int TgyBackend::read_block(std::size_t i, std::uint8_t (&b)[9]) {
  const std::uint8_t reg = 0x02;
  return bus_.write_read(static_cast<std::uint8_t>(escs_[i].address), &reg, 1, b, sizeof b);
}

StartReport TgyBackend::start(TimeUs now) {
  bus_.set_time(now);
  StartReport rep;
  char line[200];
  for (std::size_t i = 0; i < size(); ++i) {
    const auto addr = static_cast<std::uint8_t>(escs_[i].address);
    int err = bus_.claim(addr);
    if (err == 0) {
      const std::uint8_t zero[3] = {0x00, 0x00, 0x00};  // neutral: arms the ESC
      err = bus_.write(addr, zero, sizeof zero);
      record(i, err, true);
    }
    std::uint8_t b[9] = {};
    if (err == 0) {
      err = read_block(i, b);
      record(i, err, false);
    }
    if (err == 0) {
      store(i, b, now);
      if (b[8] != kTgyAlive) {
        stats_[i].present = false;
        std::snprintf(line, sizeof line,
                      "ESC %s at 0x%02x on %s answered but its identifier is 0x%02x, not 0xAB: "
                      "not a BlueESC/tgy I2C ESC\n",
                      escs_[i].name.c_str(), addr, bus_.name().c_str(), b[8]);
        rep.message += line;
        rep.all_present = false;
      }
    } else {
      stats_[i].present = false;
      std::snprintf(line, sizeof line, "ESC %s: nothing at 0x%02x on %s: %s\n",
                    escs_[i].name.c_str(), addr, bus_.name().c_str(),
                    i2c::describe_errno(err).c_str());
      rep.message += line;
      rep.all_present = false;
    }
  }
  return rep;
}

void TgyBackend::write(const std::int32_t* hw, TimeUs now) {
  bus_.set_time(now);
  for (std::size_t i = 0; i < size(); ++i) {
    const auto t = static_cast<std::uint16_t>(static_cast<std::int16_t>(hw[i]));
    const std::uint8_t buf[3] = {0x00, static_cast<std::uint8_t>(t >> 8),
                                 static_cast<std::uint8_t>(t & 0xFF)};
    record(i, bus_.write(static_cast<std::uint8_t>(escs_[i].address), buf, sizeof buf), true);
    last_hw_[i] = hw[i];
  }
}

void TgyBackend::store(std::size_t i, const std::uint8_t (&b)[9], TimeUs now) {
  const TgyTelemetryRaw r = decode_tgy_telemetry(b);
  EscTelemetry& t = telemetry_[i];
  const double dt = read_before_[i] ? to_seconds(now - last_read_[i]) : 0.0;
  double rpm = 0;
  if (dt > 0 && p_.motor_poles > 0) rpm = r.pulses / dt * 60.0 / p_.motor_poles;
  t.rpm = last_hw_[i] < 0 ? -rpm : rpm;
  t.voltage = tgy_voltage(r.voltage);
  t.current = tgy_current(r.current);
  t.temperature = tgy_temperature(r.temperature);
  t.alive = r.identifier == kTgyAlive;
  t.sample_utime = now;
  last_read_[i] = now;
  read_before_[i] = 1;
}

bool TgyBackend::poll_telemetry(TimeUs now) {
  if (!p_.telemetry || size() == 0) return false;
  const std::size_t i = next_read_;
  next_read_ = (next_read_ + 1) % size();
  std::uint8_t b[9] = {};
  const int err = read_block(i, b);
  record(i, err, false);
  if (err != 0) return false;
  store(i, b, now);
  return true;
}

}  // namespace tiller::esc
