// Asahi Kasei AK09915 3-axis magnetometer on I2C (the Blue Robotics Navigator's compass, address
// 0x0C): registers, set-up, the data read and the conversion.
//
// Source: AKM, "AK09915 3-axis Electronic Compass" datasheet (register map, section 9.3 and 10;
// sensitivity 0.15 uT/LSB, section 7). Registers: WIA1 0x00 = 0x48 (company), WIA2 0x01 = 0x10
// (device), ST1 0x10 (DRDY bit 0, DOR bit 1), HXL..HZH 0x11-0x16 (int16 little-endian), TMPS 0x17,
// ST2 0x18 (HOFL bit 3: overflow; reading ST2 ends the read and releases the data registers),
// CNTL2 0x31 (MODE: 0x00 power down, 0x01 single, continuous 0x02 10 Hz, 0x04 20 Hz, 0x06 50 Hz,
// 0x08 100 Hz, 0x0C 200 Hz, 0x10 self-test), CNTL3 0x32 (SRST bit 0: soft reset).
// One sample = one 9-byte read from ST1 to ST2. Frame: the chip's axes. No allocation here.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/transport.hpp"

namespace tiller::sensors::ak09915 {

inline constexpr std::uint8_t kAddress = 0x0C;
inline constexpr std::uint8_t kRegWia1 = 0x00;
inline constexpr std::uint8_t kRegSt1 = 0x10;
inline constexpr std::uint8_t kRegCntl2 = 0x31;
inline constexpr std::uint8_t kRegCntl3 = 0x32;
inline constexpr std::uint8_t kWia1 = 0x48, kWia2 = 0x10;
inline constexpr std::uint8_t kDrdy = 0x01, kDor = 0x02, kHofl = 0x08;
inline constexpr std::uint8_t kSoftReset = 0x01;
inline constexpr std::uint8_t kModePowerDown = 0x00;
inline constexpr std::uint8_t kModeSelfTest = 0x10;
inline constexpr double kMicroTeslaPerLsb = 0.15;
inline constexpr std::int64_t kResetUs = 1000;  // power-on / reset time
inline constexpr std::size_t kReadSize = 9;     // ST1 .. ST2

using Burst = std::array<std::uint8_t, kReadSize>;

// CNTL2 mode for a continuous rate (10, 20, 50, 100, 200 Hz), or -1 for any other.
int continuous_mode(int rate_hz);

struct Sample {
  bool data_ready = false;         // ST1 DRDY
  bool overrun = false;            // ST1 DOR: a sample was skipped
  bool overflow = false;           // ST2 HOFL: |B| beyond the range, the values are not valid
  double field_ut[3] = {0, 0, 0};  // uT, chip frame
};
Sample convert(const Burst& b);

class Device {
 public:
  Device(i2c::Transport& bus, std::uint8_t address, int rate_hz)
      : bus_(bus), address_(address), mode_(static_cast<std::uint8_t>(continuous_mode(rate_hz))) {}
  // Soft reset, WIA check (EPROTO: another chip, ids in wia()), continuous mode at the rate.
  int start();
  int read(Burst& b) { return bus_.write_read(address_, &kRegSt1, 1, b.data(), b.size()); }
  std::uint16_t wia() const { return wia_; }
  std::uint8_t address() const { return address_; }

 private:
  int write(std::uint8_t reg, std::uint8_t v) { return i2c::write_reg(bus_, address_, reg, v); }
  i2c::Transport& bus_;
  std::uint8_t address_;
  std::uint8_t mode_;
  std::uint16_t wia_ = 0;
};

}  // namespace tiller::sensors::ak09915
