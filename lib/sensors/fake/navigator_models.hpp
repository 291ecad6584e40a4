// Fake models of the Blue Robotics Navigator's sensors for tests and benchmarks: register files
// that answer as the datasheets say (sensors/icm20602.hpp, ak09915.hpp, bmp280.hpp,
// ads1115.hpp), driven by the fake buses' time.
//   Icm20602Model (spi::FakeSpi): reset to the power-on registers, WHO_AM_I 0x12, auto-increment
//     reads with bit 7, a new sample every (1 + SMPLRT_DIV) ms sets DATA_RDY_INT (cleared when
//     INT_STATUS is read); the outputs are `accel` (m/s^2) and `gyro` (rad/s) scaled by the
//     ranges written, plus `self_test_lsb` while the self-test bits are set.
//   Ak09915Model (i2c::FakeBus, 0x0C): WIA 0x48 0x10, continuous modes set DRDY at their rate,
//     reading ST2 clears it; `field_ut` in uT.
//   Bmp280Model (0x76): the datasheet's example trimming words and raw values.
//   Ads1115Model (0x48): single-shot conversions of `input_v[4]`, ready 1 / DR after the start.
#pragma once

#include <array>
#include <cstdint>

#include "i2c/fake_bus.hpp"
#include "spi/fake_spi.hpp"

namespace tiller::sensors::fake {

class Icm20602Model : public spi::FakeSpiDevice {
 public:
  Icm20602Model() { reset(); }
  void on_transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;
  std::array<std::uint8_t, 128> regs{};
  double accel[3] = {0, 0, 9.80665};  // m/s^2 chip frame (flat, package up)
  double gyro[3] = {0, 0, 0};         // rad/s
  double temperature_c = 30.0;
  double self_test_lsb = 3000;  // self-test response at FS 0 (LSB), every axis
  std::int64_t resets = 0, samples = 0;

 private:
  void reset();
  void latch();
  TimeUs next_sample_ = 0;
};

class Ak09915Model : public i2c::FakeDevice {
 public:
  Ak09915Model() { reset(); }
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;
  std::array<std::uint8_t, 64> regs{};
  double field_ut[3] = {20, 0, 40};  // chip frame
  std::uint8_t wia2 = 0x10;          // WIA2 after a reset (another AK part: 0x09 AK09916)
  bool overflow = false;

 private:
  void reset();
  std::uint8_t ptr_ = 0;
  TimeUs next_sample_ = 0;
};

class Bmp280Model : public i2c::FakeDevice {
 public:
  Bmp280Model();
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  std::array<std::uint8_t, 256> regs{};
  void set_adc(std::int32_t adc_t, std::int32_t adc_p);

 private:
  std::uint8_t ptr_ = 0;
};

class Ads1115Model : public i2c::FakeDevice {
 public:
  Ads1115Model() = default;
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;
  double input_v[4] = {0, 0, 0, 0};
  std::uint16_t config = 0x8583;
  std::uint16_t conversion = 0;
  std::int64_t conversions = 0;

 private:
  std::uint8_t ptr_ = 0;
  bool busy_ = false;
  TimeUs ready_at_ = 0;
};

// MMC5983MA (0x30): product id 0x30, continuous mode from Internal Control 2, one sample of
// `field_ut` (chip frame) per period, Meas_M_Done until the data are read.
class Mmc5983Model : public i2c::FakeDevice {
 public:
  Mmc5983Model() = default;
  int on_write(const std::uint8_t* d, std::size_t n, TimeUs now) override;
  int on_read(std::uint8_t* out, std::size_t n, TimeUs now) override;
  void advance(TimeUs now) override;
  std::array<std::uint8_t, 64> regs{};
  double field_ut[3] = {20, 0, 40};
  std::uint8_t product_id = 0x30;
  std::int64_t samples = 0;

 private:
  std::uint8_t ptr_ = 0;
  TimeUs next_sample_ = 0;
};

}  // namespace tiller::sensors::fake
