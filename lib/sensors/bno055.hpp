// Bosch BNO055 absolute orientation sensor (accelerometer, gyroscope, magnetometer and a fusion
// processor) on I2C at 0x28 (COM3 low) or 0x29: the register map, the output scaling and the
// conversion of one data burst into Tiller's body frame FRD and NED.
//
// Source: Bosch Sensortec, "BNO055 Intelligent 9-axis absolute orientation sensor", data sheet
// BST-BNO055-DS000-14, revision 1.4, June 2016 (sections 3.3 operation modes, 3.6 output data,
// 4.2-4.3 register map page 0). docs/sensors.md lists the facts used here.
//
// Page 0 registers: CHIP_ID 0x00 (reads 0xA0), PAGE_ID 0x07, data 0x08..0x33 (16-bit
// little-endian signed: ACC, MAG, GYR, EUL heading/roll/pitch, QUA w/x/y/z, LIA, GRV), TEMP
// 0x34 (int8, 1 degC = 1 LSB), CALIB_STAT 0x35 (bits 7:6 system, 5:4 gyro, 3:2 accel, 1:0 mag,
// 0..3), SYS_STATUS 0x39, SYS_ERR 0x3A, UNIT_SEL 0x3B, OPR_MODE 0x3D, PWR_MODE 0x3E,
// SYS_TRIGGER 0x3F. Scaling with UNIT_SEL = 0x00 (what the driver writes): acceleration and
// linear acceleration 1 m/s^2 = 100 LSB, angular rate 1 dps = 16 LSB, Euler angles
// 1 degree = 16 LSB, quaternion 1 = 2^14 LSB, magnetic field 1 uT = 16 LSB.
//
// Frames. The chip's axes are those printed on the board (right-handed, +Z out of the
// component side). Its fused quaternion rotates chip axes into a world frame east-north-up;
// its Euler heading (Windows format, 0..360 degrees, clockwise increasing) is the compass
// direction of the chip's +Y axis. `Mount` says which signed chip axis points along each body
// axis (forward, right, down); the default, +y/+x/-z, is the board flat, component side up,
// +Y toward the bow, for which the body yaw equals the chip's Euler heading. No allocation here.
#pragma once

#include <array>
#include <cstdint>

#include <tiller/imu_t.hpp>

#include "i2c/transport.hpp"

namespace tiller::sensors::bno055 {

inline constexpr std::uint8_t kAddressA = 0x28;  // COM3 low (the breakouts' default)
inline constexpr std::uint8_t kAddressB = 0x29;  // COM3 high
inline constexpr std::uint8_t kChipIdValue = 0xA0;

inline constexpr std::uint8_t kRegChipId = 0x00;
inline constexpr std::uint8_t kRegPageId = 0x07;
inline constexpr std::uint8_t kRegAccData = 0x08;  // first byte of the data burst
inline constexpr std::uint8_t kRegEulData = 0x1A;
inline constexpr std::uint8_t kRegQuaData = 0x20;
inline constexpr std::uint8_t kRegTemp = 0x34;
inline constexpr std::uint8_t kRegCalibStat = 0x35;
inline constexpr std::uint8_t kRegSysStatus = 0x39;
inline constexpr std::uint8_t kRegSysErr = 0x3A;
inline constexpr std::uint8_t kRegUnitSel = 0x3B;
inline constexpr std::uint8_t kRegOprMode = 0x3D;
inline constexpr std::uint8_t kRegPwrMode = 0x3E;
inline constexpr std::uint8_t kRegSysTrigger = 0x3F;

inline constexpr std::uint8_t kModeConfig = 0x00;
inline constexpr std::uint8_t kModeNdofFmcOff = 0x0B;
inline constexpr std::uint8_t kModeNdof = 0x0C;
inline constexpr std::uint8_t kPwrNormal = 0x00;
inline constexpr std::uint8_t kUnitSel = 0x00;  // m/s^2, dps, degrees, degC, Windows format

inline constexpr std::uint8_t kSysStatusError = 1;
inline constexpr std::uint8_t kSysStatusFusionRunning = 5;

// Mode switching times (data sheet table 3-6).
inline constexpr std::int64_t kToConfigUs = 19'000;   // any mode -> CONFIGMODE
inline constexpr std::int64_t kFromConfigUs = 7'000;  // CONFIGMODE -> any mode

inline constexpr double kAccLsbPerMs2 = 100.0;
inline constexpr double kGyrLsbPerDps = 16.0;
inline constexpr double kEulLsbPerDeg = 16.0;
inline constexpr double kQuaLsb = 16384.0;  // 2^14

// One burst read from ACC_DATA_X_LSB (0x08) to OPR_MODE (0x3D): the samples, TEMP, CALIB_STAT,
// ST_RESULT, INT_STA, SYS_CLK_STATUS, SYS_STATUS, SYS_ERR, UNIT_SEL, reserved, OPR_MODE.
inline constexpr std::size_t kBurstBytes = kRegOprMode - kRegAccData + 1;  // 54
using Burst = std::array<std::uint8_t, kBurstBytes>;

// The raw registers of one burst (LSB units).
struct Raw {
  std::array<std::int16_t, 3> acc{}, mag{}, gyr{}, lia{}, grv{};
  std::array<std::int16_t, 3> eul{};  // heading, roll, pitch
  std::array<std::int16_t, 4> qua{};  // w, x, y, z
  std::int8_t temp = 0;
  std::uint8_t calib_stat = 0, sys_status = 0, sys_err = 0, unit_sel = 0, opr_mode = 0;
};
Raw decode(const Burst& b);

// The chip axis (0 = x, 1 = y, 2 = z) and sign along each body axis (forward, right, down).
struct Mount {
  std::array<int, 3> axis{1, 0, 2};
  std::array<int, 3> sign{+1, +1, -1};
};
// True when the mount is a rotation (each chip axis used once, determinant +1).
bool is_rotation(const Mount& m);

// Calibration levels 0..3 from CALIB_STAT.
struct Calibration {
  std::int8_t system = 0, gyro = 0, accel = 0, mag = 0;
};
Calibration calibration(std::uint8_t calib_stat);

// Fills imu_t's measurements from a burst: angular rate (rad/s) and specific force (m/s^2) in
// body FRD, orientation body -> NED rotated by `declination_rad` about down (0: magnetic
// north; the caller sets heading_is_magnetic), calibration, temperature. orientation_valid = fusion
// running and the quaternion's norm in [0.99, 1.01]; the caller adds its own conditions
// (calibration level). Returns the body yaw in (-pi, pi] from the orientation.
double convert(const Raw& raw, const Mount& mount, double declination_rad, imu_t& out);

// The chip's own Euler heading in rad, wrapped to (-pi, pi] (0..360 deg clockwise on the chip).
double euler_heading_rad(const Raw& raw);

// "system error: fusion algorithm configuration error (SYS_ERR 0x09)" etc.
const char* sys_error_text(std::uint8_t sys_err);

}  // namespace tiller::sensors::bno055
