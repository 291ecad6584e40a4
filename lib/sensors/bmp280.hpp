// Bosch BMP280 barometer on I2C (the Blue Robotics Navigator's board pressure and temperature,
// address 0x76): registers, set-up, the calibration words and the datasheet's compensation.
//
// Source: Bosch Sensortec, "BMP280 Digital Pressure Sensor" datasheet BST-BMP280-DS001:
// memory map (section 4.2), trimming parameters (3.11.2: dig_T1..dig_P9 at 0x88..0x9F, little-
// endian, T1 and P1 unsigned), the 32-bit temperature and 64-bit pressure compensation code
// (3.11.3: T in 0.01 degC, p in Pa as Q24.8), the double-precision code (8.1) and its worked
// example (section 8.2:
// adc_T 519888, adc_P 415148 -> 25.08 degC, 100653.27 Pa). Registers: id 0xD0 = 0x58, reset
// 0xE0 <- 0xB6 (start-up 2 ms), status 0xF3 (measuring bit 3), ctrl_meas 0xF4 (osrs_t 7:5,
// osrs_p 4:2, mode 1:0 = 3 normal), config 0xF5 (t_sb 7:5, filter 4:2), press_msb 0xF7 ..
// temp_xlsb 0xFC (20-bit values, msb lsb xlsb[7:4]). One sample = one 6-byte burst from 0xF7.
// No allocation here.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/transport.hpp"

namespace tiller::sensors::bmp280 {

inline constexpr std::uint8_t kAddress = 0x76;
inline constexpr std::uint8_t kRegCalib = 0x88;
inline constexpr std::uint8_t kRegId = 0xD0;
inline constexpr std::uint8_t kRegReset = 0xE0;
inline constexpr std::uint8_t kRegCtrlMeas = 0xF4;
inline constexpr std::uint8_t kRegConfig = 0xF5;
inline constexpr std::uint8_t kRegPressMsb = 0xF7;
inline constexpr std::uint8_t kChipId = 0x58;
inline constexpr std::uint8_t kResetValue = 0xB6;
inline constexpr std::int64_t kStartUs = 2000;

struct Calibration {
  std::uint16_t t1 = 0;
  std::int16_t t2 = 0, t3 = 0;
  std::uint16_t p1 = 0;
  std::int16_t p2 = 0, p3 = 0, p4 = 0, p5 = 0, p6 = 0, p7 = 0, p8 = 0, p9 = 0;
};
// The 24 bytes from 0x88 -> the trimming parameters.
Calibration decode_calibration(const std::array<std::uint8_t, 24>& b);

struct Result {
  std::int32_t t_fine = 0;
  std::int32_t temperature_centi_c = 0;  // 0.01 degC
  std::uint32_t pressure_q24_8 = 0;      // Pa * 256 (0: the calibration is broken, P1 = 0)
  double temperature_c = 0;              // double-precision code
  double pressure_pa = 0;                // double-precision code (0: P1 = 0)
};
// The datasheet's integer compensation (3.11.3) of raw 20-bit adc_T and adc_P: t_fine, T in
// 0.01 degC and p as Q24.8 (the example: 2508, 25767236 = 100653.25 Pa); temperature_c and
// pressure_pa from the double-precision code (8.1, the example's 25.08 degC and 100653.27 Pa),
// which read() uses.
Result compensate(const Calibration& c, std::int32_t adc_t, std::int32_t adc_p);
// The burst from 0xF7 -> adc_P, adc_T.
void decode_adc(const std::array<std::uint8_t, 6>& b, std::int32_t& adc_p, std::int32_t& adc_t);

// Oversampling x1..x16 (code 1..5), IIR filter coefficient 0/2/4/8/16 (code 0..4), standby
// t_sb code 0..7 (0.5 ms .. 4000 ms). Defaults: the datasheet's "indoor navigation" setting
// (x16 pressure, x2 temperature, filter 16, 0.5 ms).
struct Config {
  std::uint8_t osrs_t = 2, osrs_p = 5, filter = 4, t_sb = 0;
};

class Device {
 public:
  Device(i2c::Transport& bus, std::uint8_t address, const Config& c)
      : bus_(bus), address_(address), c_(c) {}
  // Reset, id check (EPROTO: another chip, id in chip_id()), calibration (EBADMSG: dig_P1 0),
  // config, normal mode.
  int start();
  // One burst and the compensation.
  int read(Result& r);
  const Calibration& calibration() const { return cal_; }
  std::uint8_t chip_id() const { return id_; }

 private:
  int write(std::uint8_t reg, std::uint8_t v) { return i2c::write_reg(bus_, address_, reg, v); }
  i2c::Transport& bus_;
  std::uint8_t address_;
  Config c_;
  Calibration cal_;
  std::uint8_t id_ = 0;
};

}  // namespace tiller::sensors::bmp280
