// TDK InvenSense ICM-20602 6-axis IMU (gyro, accelerometer, temperature) on SPI (the Blue
// Robotics Navigator's IMU): registers, set-up, the data-ready burst, conversions and the
// self-test.
//
// Source: TDK InvenSense, "ICM-20602 High Performance 6-Axis MEMS MotionTracking Device"
// datasheet DS-000176 rev 1.0: register map (section 11), sensitivity tables (3.1, 3.2: gyro
// 131 / 65.5 / 32.8 / 16.4 LSB/(deg/s) for +-250..2000 deg/s; accel 16384 / 8192 / 4096 / 2048
// LSB/g for +-2..16 g), TEMP_degC = TEMP_OUT / 326.8 + 25 (section 11.23), the self-test
// (section 4.25 and the factory trim SELF_TEST_* registers, ST_OTP = 2620 / 2^FS * 1.01^(code -
// 1)). SPI: read = 0x80 | reg, up to 10 MHz for the data registers, mode 0 or 3.
// Registers used: SELF_TEST_X/Y/Z_ACCEL 0x0D-0x0F, SMPLRT_DIV 0x19, CONFIG 0x1A (DLPF_CFG 2:0),
// GYRO_CONFIG 0x1B (XG/YG/ZG_ST 7:5, FS_SEL 4:3), ACCEL_CONFIG 0x1C (XA/YA/ZA_ST 7:5,
// ACCEL_FS_SEL 4:3), ACCEL_CONFIG2 0x1D (A_DLPF_CFG 2:0), INT_ENABLE 0x38 (DATA_RDY_INT_EN bit
// 0), INT_STATUS 0x3A (DATA_RDY_INT bit 0, cleared on read), ACCEL_XOUT_H 0x3B .. GYRO_ZOUT_L
// 0x48 (big-endian int16: accel x y z, temperature, gyro x y z), SELF_TEST_X/Y/Z_GYRO 0x50-0x52,
// USER_CTRL 0x6A, PWR_MGMT_1 0x6B (DEVICE_RESET 0x80, SLEEP 0x40, CLKSEL 1 = PLL), PWR_MGMT_2
// 0x6C, I2C_IF 0x70 (I2C_IF_DIS 0x40: SPI only), WHO_AM_I 0x75 = 0x12.
// One sample = one 15-byte burst from INT_STATUS (the flag and the 14 data bytes together).
// Frame: the chip's own axes (x, y, z as printed on the package); the node's `mount` (the
// same form as tiller-imu's, sensors/imu_node.hpp) turns them into body FRD. No allocation anywhere
// here.
#pragma once

#include <array>
#include <cstdint>

#include "spi/transport.hpp"

namespace tiller::sensors::icm20602 {

inline constexpr std::uint8_t kRegSelfTestXAccel = 0x0D;
inline constexpr std::uint8_t kRegSmplrtDiv = 0x19;
inline constexpr std::uint8_t kRegConfig = 0x1A;
inline constexpr std::uint8_t kRegGyroConfig = 0x1B;
inline constexpr std::uint8_t kRegAccelConfig = 0x1C;
inline constexpr std::uint8_t kRegAccelConfig2 = 0x1D;
inline constexpr std::uint8_t kRegIntEnable = 0x38;
inline constexpr std::uint8_t kRegIntStatus = 0x3A;
inline constexpr std::uint8_t kRegAccelXoutH = 0x3B;
inline constexpr std::uint8_t kRegSelfTestXGyro = 0x50;
inline constexpr std::uint8_t kRegUserCtrl = 0x6A;
inline constexpr std::uint8_t kRegPwrMgmt1 = 0x6B;
inline constexpr std::uint8_t kRegPwrMgmt2 = 0x6C;
inline constexpr std::uint8_t kRegI2cIf = 0x70;
inline constexpr std::uint8_t kRegWhoAmI = 0x75;

inline constexpr std::uint8_t kWhoAmI = 0x12;
inline constexpr std::uint8_t kDeviceReset = 0x80;
inline constexpr std::uint8_t kClkPll = 0x01;
inline constexpr std::uint8_t kI2cIfDis = 0x40;
inline constexpr std::uint8_t kDataRdyInt = 0x01;
inline constexpr std::uint8_t kSelfTestXyz = 0xE0;  // XG/YG/ZG_ST or XA/YA/ZA_ST
inline constexpr std::int64_t kResetUs =
    100'000;                                   // start-up after DEVICE_RESET (datasheet: 100 ms)
inline constexpr std::size_t kBurstSize = 15;  // INT_STATUS + 14 data bytes
inline constexpr double kTempSensitivity = 326.8;  // LSB/degC
inline constexpr double kTempOffsetC = 25.0;
inline constexpr double kG = 9.80665;  // m/s^2 per g

using Burst = std::array<std::uint8_t, kBurstSize>;

// Full-scale ranges: code 0..3 (FS_SEL, ACCEL_FS_SEL).
enum class GyroRange : std::uint8_t { dps250 = 0, dps500 = 1, dps1000 = 2, dps2000 = 3 };
enum class AccelRange : std::uint8_t { g2 = 0, g4 = 1, g8 = 2, g16 = 3 };
double gyro_lsb_per_dps(GyroRange r);  // 131, 65.5, 32.8, 16.4
double accel_lsb_per_g(AccelRange r);  // 16384, 8192, 4096, 2048

struct Config {
  GyroRange gyro_range = GyroRange::dps1000;
  AccelRange accel_range = AccelRange::g8;
  std::uint8_t dlpf_cfg = 2;         // gyro and temperature low-pass: 2 = 92 Hz (1 kHz rate)
  std::uint8_t accel_dlpf_cfg = 2;   // 2 = 99 Hz
  std::uint8_t sample_rate_div = 9;  // 1 kHz / (1 + div): 9 -> 100 Hz
};

// The register writes of a set-up after reset, in order ({reg, value}).
std::array<std::array<std::uint8_t, 2>, 8> setup_writes(const Config& c);

// One decoded sample in the chip frame and SI units.
struct Sample {
  bool data_ready = false;      // INT_STATUS DATA_RDY_INT: new data since the last burst
  double gyro[3] = {0, 0, 0};   // rad/s
  double accel[3] = {0, 0, 0};  // m/s^2 (specific force: +1 g up on z when flat, package up)
  double temperature_c = 0;
};
Sample convert(const Burst& b, const Config& c);
inline std::int16_t be16(const std::uint8_t* p) {
  return static_cast<std::int16_t>((p[0] << 8) | p[1]);
}

// Factory self-test response for a SELF_TEST_* code at FS 0 (LSB), 0 when the code is 0.
double factory_self_test(std::uint8_t code);
// Self-test verdict of one axis: the response (self-test on minus off, LSB at FS 0) over the
// factory value. Gyro passes at >= 0.5; accel within 0.5 .. 1.5 (datasheet table 4).
struct SelfTest {
  double gyro_ratio[3] = {0, 0, 0};
  double accel_ratio[3] = {0, 0, 0};
  bool passed = false;
};

class Device {
 public:
  Device(spi::Transport& bus, const Config& c) : bus_(bus), c_(c) {}
  // Reset, WHO_AM_I check (ENODEV: no answer 0x00/0xFF; EPROTO: another chip, id in who_am_i()),
  // I2C off, ranges, filters, sample rate, data-ready flag. Blocks kResetUs (set-up only).
  int start();
  // One burst (INT_STATUS + data): 0 or an errno.
  int read(Burst& b) { return bus_.read_regs(kRegIntStatus, b.data(), b.size()); }
  // Self-test at FS 0 (average of `samples` samples each way), then start() again.
  int self_test(int samples, SelfTest& out);
  std::uint8_t who_am_i() const { return who_am_i_; }
  const Config& config() const { return c_; }

 private:
  int average(int samples, double accel[3], double gyro[3]);
  spi::Transport& bus_;
  Config c_;
  std::uint8_t who_am_i_ = 0;
};

}  // namespace tiller::sensors::icm20602
