// TI ADS1115 16-bit ADC on I2C (the Blue Robotics Navigator's ADC, address 0x48): the config
// word, single-shot conversions, the conversion, and the power module's scaling.
//
// Source: Texas Instruments, "ADS111x Ultra-Small, Low-Power, I2C-Compatible, 860-SPS, 16-Bit
// ADCs", SBAS444: register map (8.6: conversion 0x00, config 0x01, Lo_thresh 0x02, Hi_thresh
// 0x03, 16-bit big-endian), config register (table 8-3: OS bit 15 (write 1: start a single
// conversion; read 1: idle), MUX 14:12 (4 + n: AINn against GND), PGA 11:9 (0 +-6.144 V, 1
// +-4.096, 2 +-2.048 (reset), 3 +-1.024, 4 +-0.512, 5..7 +-0.256), MODE bit 8 (1 single-shot),
// DR 7:5 (8, 16, 32, 64, 128, 250, 475, 860 SPS), COMP_QUE 1:0 = 3 comparator off; reset value
// 0x8583), output codes (table 8-1: LSB = FSR / 2^15, 0x7FFF = +FSR (2^15 - 1) / 2^15), data rate
// accuracy +-10% (7.5): a conversion is read 1.1 / DR after it was started.
// No allocation here.
#pragma once

#include <cstdint>

#include "i2c/transport.hpp"

namespace tiller::sensors::ads1115 {

inline constexpr std::uint8_t kAddress = 0x48;
inline constexpr std::uint8_t kRegConversion = 0x00;
inline constexpr std::uint8_t kRegConfig = 0x01;
inline constexpr std::uint16_t kConfigReset = 0x8583;
inline constexpr std::uint16_t kOs = 0x8000;

// Full-scale range of a PGA code (V), and the code for a range (-1 if not one of the six).
double full_scale_v(int pga_code);
int pga_code(double full_scale_v);
// Data rate code for 8..860 SPS, or -1.
int data_rate_code(int sps);
int data_rate_sps(int code);
// The config word starting one single-shot conversion of AIN<channel> against GND.
std::uint16_t single_shot_word(int channel, int pga_code, int dr_code);
// Time from the start of a conversion to a safe read (us): 1.1 / DR.
std::int64_t conversion_us(int dr_code);
// Conversion register -> volts at the input.
inline double volts(std::uint16_t raw, int pga) {
  return static_cast<std::int16_t>(raw) * full_scale_v(pga) / 32768.0;
}

// A power module on two inputs: V_bus = divider * V_in; I = (V_in - offset) * amps_per_volt.
struct PowerModule {
  int voltage_channel = 2;
  int current_channel = 3;
  double voltage_divider = 11.0;  // V per V
  double amps_per_volt = 37.8788;
  double current_offset_v = 0.330;
};

class Device {
 public:
  Device(i2c::Transport& bus, std::uint8_t address, int pga, int dr)
      : bus_(bus), address_(address), pga_(pga), dr_(dr) {}
  // Reads the config register back: 0, or EPROTO when it does not look like an ADS1115 (bits
  // 4:0 of the reset word 0x8583 are comparator settings nobody else here writes).
  int probe();
  // Starts a single conversion of AIN<channel>; read conversion_us(dr) later.
  int start(int channel);
  int read(std::uint16_t& raw);
  int pga() const { return pga_; }
  int dr() const { return dr_; }
  std::uint8_t address() const { return address_; }

 private:
  i2c::Transport& bus_;
  std::uint8_t address_;
  int pga_, dr_;
};

}  // namespace tiller::sensors::ads1115
