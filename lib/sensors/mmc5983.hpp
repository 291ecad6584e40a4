// MEMSIC MMC5983MA 3-axis magnetometer on I2C (the compass of Blue Robotics Navigator revisions
// that carry no AK09915; address 0x30): registers, set-up, the data read and the conversion.
//
// Source: MEMSIC, "MMC5983MA Low Noise, High Accuracy 3-axis Magnetic Sensor" datasheet
// (register map: Xout0 0x00 .. Zout1 0x05, XYZout2 0x06 (the two low bits of each axis: X 7:6,
// Y 5:4, Z 3:2), Tout 0x07, Status 0x08 (Meas_M_Done bit 0), Internal Control 0 0x09 (TM_M bit
// 0, Auto_SR_en bit 5), Internal Control 1 0x0A (BW 1:0; SW_RST bit 7), Internal Control 2 0x0B
// (Cm_freq 2:0: 1 = 1 Hz, 2 = 10, 3 = 20, 4 = 50, 5 = 100 Hz at BW 00; Cmm_en bit 3 continuous
// mode; Prd_set 6:4; En_prd_set bit 7), Product ID 0x2F = 0x30; 18-bit output, null field
// 131072, 16384 counts per gauss (0.0625 mG, 6.1 nT per count), range +-8 G; 10 ms after a
// software reset). One sample = one 9-byte read from Xout0 to Status in continuous mode, with
// the automatic SET/RESET (which removes the bridge offset) at every measurement. Frame: the
// chip's axes. No allocation here.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/transport.hpp"

namespace tiller::sensors::mmc5983 {

inline constexpr std::uint8_t kAddress = 0x30;
inline constexpr std::uint8_t kRegXout0 = 0x00;
inline constexpr std::uint8_t kRegStatus = 0x08;
inline constexpr std::uint8_t kRegControl0 = 0x09;
inline constexpr std::uint8_t kRegControl1 = 0x0A;
inline constexpr std::uint8_t kRegControl2 = 0x0B;
inline constexpr std::uint8_t kRegProductId = 0x2F;
inline constexpr std::uint8_t kProductId = 0x30;
inline constexpr std::uint8_t kMeasDone = 0x01;
inline constexpr std::uint8_t kAutoSetReset = 0x20;
inline constexpr std::uint8_t kSoftReset = 0x80;
inline constexpr std::uint8_t kContinuous = 0x08;
inline constexpr std::uint8_t kPeriodicSet = 0x80;  // with Prd_set 000: at every measurement
inline constexpr std::int64_t kResetUs = 10'000;
inline constexpr double kNull = 131072.0;
inline constexpr double kCountsPerGauss = 16384.0;
inline constexpr std::size_t kReadSize = 9;  // Xout0 .. Status

using Burst = std::array<std::uint8_t, kReadSize>;

// Cm_freq for a continuous rate (1, 10, 20, 50, 100 Hz at the 100 Hz bandwidth), or -1.
int continuous_freq(int rate_hz);

struct Sample {
  bool data_ready = false;         // Status Meas_M_Done
  double field_ut[3] = {0, 0, 0};  // uT, chip frame (1 G = 100 uT)
};
Sample convert(const Burst& b);

class Device {
 public:
  Device(i2c::Transport& bus, std::uint8_t address, int rate_hz)
      : bus_(bus), address_(address), freq_(static_cast<std::uint8_t>(continuous_freq(rate_hz))) {}
  // Software reset, product id check (EPROTO: another chip, its id in product_id()), automatic
  // SET/RESET, continuous mode at the rate.
  int start();
  int read(Burst& b) { return bus_.write_read(address_, &kRegXout0, 1, b.data(), b.size()); }
  std::uint8_t product_id() const { return id_; }
  std::uint8_t address() const { return address_; }

 private:
  int write(std::uint8_t reg, std::uint8_t v) { return i2c::write_reg(bus_, address_, reg, v); }
  i2c::Transport& bus_;
  std::uint8_t address_;
  std::uint8_t freq_;
  std::uint8_t id_ = 0;
};

}  // namespace tiller::sensors::mmc5983
