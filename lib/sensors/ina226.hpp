// TI INA226 current, voltage and power monitor on I2C (0x40..0x4F, set by A0/A1): registers,
// the calibration value, the conversions, and the charge and energy integrator.
//
// Source: Texas Instruments, "INA226 High-Side or Low-Side Measurement, Bi-Directional Current
// and Power Monitor with I2C Compatible Interface", SBOS547 (June 2011; rev. B, 2024): register
// map (table 7-1), Configuration register, equations 1-4, and the configure / measure /
// calculate example (table 1). docs/sensors.md lists the facts used here.
//
// Registers are 16-bit big-endian; a read is a pointer write then two bytes (no
// auto-increment). Configuration 0x00 (power-on 0x4127: bit 14 reads 1, AVG bits 11:9,
// VBUSCT 8:6, VSHCT 5:3, MODE 2:0 = 7 shunt and bus continuous; bit 15 resets), shunt voltage
// 0x01 (signed, 2.5 uV/LSB), bus voltage 0x02 (1.25 mV/LSB), power 0x03 (25 x Current_LSB W),
// current 0x04 (signed, Current_LSB A), calibration 0x05, mask/enable 0x06, alert limit 0x07,
// manufacturer id 0xFE (0x5449, "TI"), die id 0xFF (0x2260).
// CAL = trunc(0.00512 / (Current_LSB * R_shunt)); the chip computes Current = Shunt * CAL /
// 2048 and Power = Current * Bus / 20000. No allocation here.
#pragma once

#include <cstdint>

#include "core/time.hpp"

namespace tiller::sensors::ina226 {

inline constexpr std::uint8_t kRegConfig = 0x00;
inline constexpr std::uint8_t kRegShunt = 0x01;
inline constexpr std::uint8_t kRegBus = 0x02;
inline constexpr std::uint8_t kRegPower = 0x03;
inline constexpr std::uint8_t kRegCurrent = 0x04;
inline constexpr std::uint8_t kRegCalibration = 0x05;
inline constexpr std::uint8_t kRegMaskEnable = 0x06;
inline constexpr std::uint8_t kRegAlertLimit = 0x07;
inline constexpr std::uint8_t kRegManufacturerId = 0xFE;
inline constexpr std::uint8_t kRegDieId = 0xFF;

inline constexpr std::uint16_t kManufacturerId = 0x5449;
inline constexpr std::uint16_t kDieId = 0x2260;
inline constexpr std::uint16_t kConfigPowerOn = 0x4127;
inline constexpr std::uint16_t kConfigReset = 0x8000;

inline constexpr double kShuntLsbV = 2.5e-6;
inline constexpr double kBusLsbV = 1.25e-3;
inline constexpr double kPowerLsbPerCurrentLsb = 25.0;

// The calibration register for a current LSB (A) and a shunt (ohm); 0 when it does not fit
// the register's 15 bits (1..32767): the LSB is too fine or too coarse for that shunt.
std::uint16_t calibration(double current_lsb_a, double shunt_ohm);

// Averaging count (1, 4, 16, 64, 128, 256, 512, 1024) and conversion time (140, 204, 332,
// 588, 1100, 2116, 4156, 8244 us) -> their 3-bit codes, or -1 for any other value.
int averaging_code(int samples);
int conversion_time_code(int us);
// The configuration word: bit 14 set, shunt and bus continuous (MODE 7).
std::uint16_t config_word(int avg_code, int vbus_ct_code, int vsh_ct_code);
// Time for one averaged result of both channels (us): avg * (vbus_ct + vsh_ct).
std::int64_t sample_period_us(int avg_samples, int vbus_ct_us, int vsh_ct_us);

// Register values -> SI units.
inline double shunt_voltage(std::uint16_t raw) {
  return static_cast<std::int16_t>(raw) * kShuntLsbV;
}
inline double bus_voltage(std::uint16_t raw) {
  return raw * kBusLsbV;
}
inline double current(std::uint16_t raw, double current_lsb) {
  return static_cast<std::int16_t>(raw) * current_lsb;
}
inline double power(std::uint16_t raw, double current_lsb) {
  return raw * kPowerLsbPerCurrentLsb * current_lsb;
}

// Consumed charge (Ah) and energy (Wh), integrated by the trapezoid rule over the times of the
// samples it is given. A gap longer than max_gap between two samples is not integrated (the
// charge drawn then is unknown) and counted in gaps().
class Integrator {
 public:
  explicit Integrator(TimeUs max_gap) : max_gap_(max_gap) {}
  void add(TimeUs t, double current_a, double power_w);
  double charge_ah() const { return charge_as_ / 3600.0; }
  double energy_wh() const { return energy_ws_ / 3600.0; }
  std::int64_t gaps() const { return gaps_; }

 private:
  TimeUs max_gap_;
  bool have_ = false;
  TimeUs t_ = 0;
  double i_ = 0, p_ = 0;
  double charge_as_ = 0, energy_ws_ = 0;
  std::int64_t gaps_ = 0;
};

}  // namespace tiller::sensors::ina226
