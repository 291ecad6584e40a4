// MS5837 pressure sensor (TE Connectivity MS5837-30BA: Blue Robotics Bar30; MS5837-02BA: Bar02)
// on I2C at 0x76: the protocol, the PROM CRC-4 and the datasheet's temperature compensation.
//
// Source: TE Connectivity, "MS5837-30BA Ultra Small Gel Filled Pressure Sensor" datasheet
// (pressure and temperature calculation, second order temperature compensation, CRC-4 code)
// and "MS5837-02BA" datasheet (same layout, other coefficients' scaling). docs/sensors.md has
// the facts used here. Integer arithmetic as in the datasheet: every "/ 2^n" is an arithmetic
// shift (floor), which is what reproduces the datasheet's worked example (TEMP = 1981, not the
// 1982 of a truncating division).
//
// Commands: reset 0x1E; PROM read 0xA0 + 2k (k = 0..6, 16-bit big-endian words; word 0 holds the
// CRC in bits 15..12); convert D1 (pressure) 0x40 | osr, D2 (temperature) 0x50 | osr, osr code
// 0x00 (OSR 256) .. 0x0A (OSR 8192); ADC read 0x00 (24 bits big-endian, 0 if read before the
// conversion ended). No allocation anywhere here.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/transport.hpp"

namespace tiller::sensors::ms5837 {

enum class Model { ba30, ba02 };

inline constexpr std::uint8_t kAddress = 0x76;
inline constexpr std::uint8_t kCmdReset = 0x1E;
inline constexpr std::uint8_t kCmdPromRead = 0xA0;
inline constexpr std::uint8_t kCmdConvertD1 = 0x40;
inline constexpr std::uint8_t kCmdConvertD2 = 0x50;
inline constexpr std::uint8_t kCmdAdcRead = 0x00;
inline constexpr std::int64_t kResetUs = 3000;  // PROM reload after reset (datasheet: 2.8 ms)

using Prom = std::array<std::uint16_t, 7>;  // word 0 (CRC, factory), C1..C6

// The CRC-4 of the PROM (datasheet's code: word 0's CRC nibble zeroed, an eighth word of 0,
// polynomial 0x3000 over the 16 bytes MSB first).
std::uint8_t crc4(const Prom& prom);
inline bool prom_valid(const Prom& prom) {
  return crc4(prom) == (prom[0] >> 12);
}

// OSR 256, 512, ..., 8192: the command's low bits (0x00..0x0A) and the maximum conversion time.
struct Osr {
  int ratio = 0;
  std::uint8_t code = 0;
  std::int64_t max_conversion_us = 0;
};
// The OSR for a ratio, or one with ratio 0 if it is not one of the six.
Osr osr_for(int ratio);

// Intermediate and final values of the calculation (datasheet variable names).
struct Result {
  std::int32_t dT = 0;
  std::int32_t temp = 0;  // 0.01 degC, first order
  std::int64_t off = 0, sens = 0;
  std::int32_t p = 0;        // first order, in the model's unit (30BA 0.1 mbar, 02BA 0.01 mbar)
  std::int32_t temp2 = 0;    // 0.01 degC, after the second order step
  std::int32_t p2 = 0;       // after the second order step, same unit as p
  double temperature_c = 0;  // temp2 / 100
  double pressure_pa = 0;    // p2 in Pa
};

// First and second order compensation of raw D1 (pressure) and D2 (temperature).
Result compensate(Model model, const Prom& prom, std::uint32_t d1, std::uint32_t d2);

// The device on a bus. start() resets it and reads and checks the PROM; then a sample is
// start_conversion(D1 or D2), at least max_conversion_us later read_adc(). Each call returns 0
// or an errno value (EBADMSG: PROM CRC mismatch; EAGAIN: ADC read 0, conversion not finished).
class Device {
 public:
  Device(i2c::Transport& bus, std::uint8_t address, Model model, Osr osr)
      : bus_(bus), address_(address), model_(model), osr_(osr) {}
  int start();
  int start_conversion(bool pressure);
  int read_adc(std::uint32_t& value);
  const Prom& prom() const { return prom_; }
  Model model() const { return model_; }
  std::uint8_t address() const { return address_; }

 private:
  i2c::Transport& bus_;
  std::uint8_t address_;
  Model model_;
  Osr osr_;
  Prom prom_{};
};

}  // namespace tiller::sensors::ms5837
