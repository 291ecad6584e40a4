// BlueESC / tgy (SIMPLE_I2C build) ESCs on I2C, seed 000: 16-bit signed throttle.
//
// Register map (docs/escs-and-wiring.md, from Blue Robotics' tgy fork; the register pointer
// auto-increments):
//   0x00-0x01 W  throttle int16 big-endian, +-32767 full, negative = reverse
//   0x02-0x03 R  commutation pulses since the last read (the read clears them)
//   0x04-0x05 R  battery voltage raw: V = raw / 65536 * 5 * 6.45
//   0x06-0x07 R  temperature raw from a 10 kOhm NTC (B 3900) with 3.3 kOhm in series
//   0x08-0x09 R  current raw: A = (raw - 32767) / 65535 * 5 * 14.706
//   0x0A      R  0xAB "alive" identifier
// Each cycle: one 3-byte write [0x00, hi, lo] per ESC (never SMBus word calls: those are
// little-endian), then at most one telemetry read (write [0x02], read 9 bytes) for one ESC in
// round robin, so the throttle rate stays as high as the bus allows.
// RPM = pulses / dt * 60 / motor_poles, dt = time since that ESC's previous read.
#pragma once

#include <array>
#include <string>

#include "esc/backend.hpp"
#include "i2c/transport.hpp"

namespace tiller::esc {

struct TgyParams {
  std::string bus = "/dev/i2c-1";
  bool telemetry = true;  // round-robin telemetry reads
  int motor_poles = 14;   // T200: 14, T100: 12
};

// Decoded 9-byte telemetry block (registers 0x02..0x0A).
struct TgyTelemetryRaw {
  std::uint16_t pulses = 0, voltage = 0, temperature = 0, current = 0;
  std::uint8_t identifier = 0;
};
TgyTelemetryRaw decode_tgy_telemetry(const std::uint8_t (&b)[9]);
double tgy_voltage(std::uint16_t raw);      // V
double tgy_current(std::uint16_t raw);      // A
double tgy_temperature(std::uint16_t raw);  // degC (NaN for raw 0)
constexpr std::uint8_t kTgyAlive = 0xAB;

class TgyBackend : public EscBackend {
 public:
  TgyBackend(i2c::Transport& bus, TgyParams p, std::vector<EscChannelParams> escs);
  std::int8_t unit() const override;
  std::string bus() const override { return bus_.name(); }
  bool has_telemetry() const override { return p_.telemetry; }
  StartReport start(TimeUs now) override;
  std::int32_t to_hardware(std::size_t i, double u) const override;
  double to_normalized(std::size_t i, std::int32_t hw) const override;
  void write(const std::int32_t* hw, TimeUs now) override;
  bool poll_telemetry(TimeUs now) override;

 private:
  int read_block(std::size_t i, std::uint8_t (&b)[9]);
  void store(std::size_t i, const std::uint8_t (&b)[9], TimeUs now);

  i2c::Transport& bus_;
  TgyParams p_;
  std::vector<std::int32_t> last_hw_;  // sign of the RPM
  std::vector<TimeUs> last_read_;      // previous read per ESC (pulses accumulate since)
  std::vector<std::uint8_t> read_before_;
  std::size_t next_read_ = 0;
};

}  // namespace tiller::esc
