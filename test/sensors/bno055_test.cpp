// BNO055 (sensors/bno055.hpp, sensors/imu_node.hpp): the data sheet's scaling with
// hand-computed register values, the frames (chip -> body FRD, ENU -> NED, mounts), and
// tiller-imu's node on the fake bus (set-up timing, samples, missing device, wrong chip, reset,
// calibration, bus errors, system error, strict config).
#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <string>
#include <vector>

#include <tiller/heading_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/imu_t.hpp>

#include "core/config.hpp"
#include "i2c/fake_bus.hpp"
#include "i2c/linux_i2c.hpp"
#include "runtime/node.hpp"
#include "sensors/bno055.hpp"
#include "sensors/fake/bno055_model.hpp"
#include "sensors/imu_node.hpp"

namespace tiller::sensors {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

// A burst with the given registers (little-endian 16-bit words at their addresses).
struct BurstBuilder {
  bno055::Burst b{};
  BurstBuilder() {
    set8(bno055::kRegSysStatus, 5);
    set8(bno055::kRegOprMode, bno055::kModeNdof);
  }
  BurstBuilder& set16(std::uint8_t reg, std::int16_t v) {
    b[reg - 0x08] = static_cast<std::uint8_t>(v & 0xFF);
    b[reg - 0x08 + 1] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
    return *this;
  }
  BurstBuilder& set8(std::uint8_t reg, std::uint8_t v) {
    b[reg - 0x08] = v;
    return *this;
  }
  BurstBuilder& vec(std::uint8_t reg, std::int16_t x, std::int16_t y, std::int16_t z) {
    return set16(reg, x).set16(reg + 2, y).set16(reg + 4, z);
  }
  BurstBuilder& quat(std::int16_t w, std::int16_t x, std::int16_t y, std::int16_t z) {
    return set16(0x20, w).set16(0x22, x).set16(0x24, y).set16(0x26, z);
  }
};

std::int16_t q14(double v) {
  return static_cast<std::int16_t>(std::lround(v * 16384));
}

TEST(Bno055, DecodeAndScaleHandComputed) {
  // Level, still, facing magnetic north: quaternion raw (16384, 0, 0, 0) = 1.0; ACC_DATA_Z 981
  // = 9.81 m/s^2 (1 m/s^2 = 100 LSB); GYR raw (16, -32, 160) = (1, -2, 10) dps (16 LSB/dps);
  // TEMP 25 degC; CALIB_STAT 0xE4 = 11 10 01 00b: system 3, gyro 2, accel 1, mag 0.
  BurstBuilder bb;
  bb.quat(16384, 0, 0, 0).vec(0x08, 0, 0, 981).vec(0x14, 16, -32, 160);
  bb.set8(bno055::kRegTemp, 25).set8(bno055::kRegCalibStat, 0xE4);
  const bno055::Raw raw = bno055::decode(bb.b);
  EXPECT_EQ(raw.qua[0], 16384);
  EXPECT_EQ(raw.acc[2], 981);
  EXPECT_EQ(raw.gyr[1], -32);
  EXPECT_EQ(raw.opr_mode, 0x0C);
  imu_t m{};
  const double yaw = bno055::convert(raw, bno055::Mount{}, 0, m);
  // Default mount: body forward = chip +y, right = chip +x, down = chip -z.
  EXPECT_DOUBLE_EQ(m.angular_rate[0], -2 * kDeg);   // p = gyro y
  EXPECT_DOUBLE_EQ(m.angular_rate[1], 1 * kDeg);    // q = gyro x
  EXPECT_DOUBLE_EQ(m.angular_rate[2], -10 * kDeg);  // r = -gyro z
  EXPECT_DOUBLE_EQ(m.specific_force[0], 0);
  EXPECT_DOUBLE_EQ(m.specific_force[1], 0);
  EXPECT_DOUBLE_EQ(m.specific_force[2], -9.81);  // the contract's level-at-rest [0 0 -9.81]
  EXPECT_TRUE(m.orientation_valid);
  EXPECT_DOUBLE_EQ(m.orientation[0], 1.0);  // body FRD = NED: identity
  EXPECT_DOUBLE_EQ(m.orientation[1], 0.0);
  EXPECT_DOUBLE_EQ(m.orientation[2], 0.0);
  EXPECT_DOUBLE_EQ(m.orientation[3], 0.0);
  EXPECT_DOUBLE_EQ(yaw, 0.0);
  EXPECT_EQ(m.calibration_system, 3);
  EXPECT_EQ(m.calibration_gyro, 2);
  EXPECT_EQ(m.calibration_accel, 1);
  EXPECT_EQ(m.calibration_mag, 0);
  EXPECT_DOUBLE_EQ(m.temperature, 25);
}

TEST(Bno055, FusedYawIsTheEulerHeadingClockwiseFromNorth) {
  // Heading psi clockwise (chip +Y toward east for 90 deg) is a rotation of -psi about ENU up:
  // q = (cos(psi/2), 0, 0, -sin(psi/2)); EUL_Heading = psi * 16 LSB (0..360 deg).
  for (double deg : {0.0, 30.0, 90.0, 179.0, 200.0, 270.0, 359.0}) {
    const double psi = deg * kDeg;
    BurstBuilder bb;
    bb.quat(q14(std::cos(psi / 2)), 0, 0, q14(-std::sin(psi / 2)));
    bb.set16(bno055::kRegEulData, static_cast<std::int16_t>(std::lround(deg * 16)));
    const bno055::Raw raw = bno055::decode(bb.b);
    imu_t m{};
    const double yaw = bno055::convert(raw, bno055::Mount{}, 0, m);
    const double expected = deg > 180 ? psi - 2 * kPi : psi;
    EXPECT_NEAR(yaw, expected, 2e-4) << deg;  // 2^-14 quantisation
    EXPECT_NEAR(bno055::euler_heading_rad(raw), expected, 1e-12) << deg;
    EXPECT_TRUE(m.orientation_valid) << deg;
    // NED quaternion of a pure yaw psi: (cos(psi/2), 0, 0, sin(psi/2)) with w >= 0.
    const double s = std::cos(expected / 2) < 0 ? -1 : 1;
    EXPECT_NEAR(m.orientation[0], s * std::cos(expected / 2), 1e-4) << deg;
    EXPECT_NEAR(m.orientation[3], s * std::sin(expected / 2), 1e-4) << deg;
  }
}

TEST(Bno055, RollTowardStarboardIsPositive) {
  // Chip rotated +30 deg about its +Y (the bow): its +X (starboard) dips. NED roll +30 deg:
  // orientation (cos 15, sin 15, 0, 0).
  BurstBuilder bb;
  bb.quat(q14(std::cos(15 * kDeg)), 0, q14(std::sin(15 * kDeg)), 0);
  imu_t m{};
  bno055::convert(bno055::decode(bb.b), bno055::Mount{}, 0, m);
  EXPECT_NEAR(m.orientation[0], std::cos(15 * kDeg), 1e-4);
  EXPECT_NEAR(m.orientation[1], std::sin(15 * kDeg), 1e-4);
  EXPECT_NEAR(m.orientation[2], 0, 1e-4);
  EXPECT_NEAR(m.orientation[3], 0, 1e-4);
}

TEST(Bno055, MountAndDeclination) {
  // Board with its +X to the bow and +Y to port (forward +x, right -y, down -z): when the chip's
  // +Y points north the bow points east: yaw +90 deg. A 10 deg east declination adds 10 deg.
  bno055::Mount mount;
  mount.axis = {0, 1, 2};
  mount.sign = {+1, -1, -1};
  ASSERT_TRUE(bno055::is_rotation(mount));
  BurstBuilder bb;
  bb.quat(16384, 0, 0, 0).vec(0x14, 16, 32, 0);
  imu_t m{};
  EXPECT_NEAR(bno055::convert(bno055::decode(bb.b), mount, 0, m), kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(m.angular_rate[0], 1 * kDeg);
  EXPECT_DOUBLE_EQ(m.angular_rate[1], -2 * kDeg);
  EXPECT_NEAR(bno055::convert(bno055::decode(bb.b), mount, 10 * kDeg, m), 100 * kDeg, 1e-12);
  // Not rotations: an axis twice, a mirror.
  bno055::Mount twice;
  twice.axis = {1, 1, 2};
  EXPECT_FALSE(bno055::is_rotation(twice));
  bno055::Mount mirror;
  mirror.sign = {+1, +1, +1};
  EXPECT_FALSE(bno055::is_rotation(mirror));
  EXPECT_TRUE(bno055::is_rotation(bno055::Mount{}));
}

TEST(Bno055, ZeroQuaternionIsNotValid) {
  BurstBuilder bb;  // fusion running but the quaternion still 0 (first samples after a start)
  imu_t m{};
  bno055::convert(bno055::decode(bb.b), bno055::Mount{}, 0, m);
  EXPECT_FALSE(m.orientation_valid);
  for (double v : m.orientation) EXPECT_TRUE(std::isfinite(v));
}

// Collects what the node publishes.
struct Capture : Bus {
  std::vector<imu_t> imu;
  std::vector<heading_t> headings;
  heartbeat_t hb;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    if (ch == "TILLER_IMU") {
      imu_t m;
      if (m.decode(d, 0, n) == n) imu.push_back(m);
    } else if (ch == "TILLER_HEADING") {
      heading_t m;
      if (m.decode(d, 0, n) == n) headings.push_back(m);
    } else if (ch == "TILLER_HEARTBEAT_IMU") {
      hb.decode(d, 0, n);
    }
  }
};

struct Rig {
  i2c::FakeBus bus{"/dev/i2c-1"};
  fake::Bno055Model dev;
  ImuParams p;
  Capture out;
  Rig() {
    dev.set_quaternion(q14(std::cos(45 * kDeg)), 0, 0, q14(-std::sin(45 * kDeg)));  // 90 deg
    dev.set_euler(90 * 16, 0, 0);
    dev.set_vector(0x08, 0, 0, 981);
    dev.set_vector(0x14, 0, 0, -16);  // turning clockwise seen from above at 1 deg/s
    dev.calib_stat = 0xFF;
    p.heading_std = 2.5 * kDeg;
  }
  void run(ImuNode& n, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += n.tick_period()) n.tick(t);
  }
};

TEST(ImuNode, SetsUpWithTheDataSheetTimesAndPublishes) {
  Rig r;
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  n.tick(0);  // CHIP_ID, CONFIGMODE
  EXPECT_EQ(r.dev.reg(bno055::kRegOprMode), bno055::kModeConfig);
  n.tick(10'000);                                   // 10 ms < 19 ms: still waiting
  EXPECT_EQ(r.dev.reg(bno055::kRegUnitSel), 0x80);  // power-on value, not written yet
  n.tick(20'000);                                   // 20 ms: units, NDOF
  EXPECT_EQ(r.dev.reg(bno055::kRegUnitSel), 0x00);
  EXPECT_EQ(r.dev.reg(bno055::kRegOprMode), bno055::kModeNdof);
  EXPECT_FALSE(n.device_ready());
  r.run(n, 40'000, kUsPerSecond);  // 40 ms: running (7 ms after NDOF), then 50 Hz
  EXPECT_TRUE(n.device_ready());
  ASSERT_EQ(r.out.imu.size(), 49u);  // 40 ms .. 1000 ms
  ASSERT_EQ(r.out.headings.size(), 49u);
  const imu_t& m = r.out.imu.back();
  EXPECT_EQ(m.utime, kUsPerSecond);
  EXPECT_TRUE(m.orientation_valid);
  EXPECT_TRUE(m.heading_is_magnetic);
  EXPECT_DOUBLE_EQ(m.specific_force[2], -9.81);
  EXPECT_DOUBLE_EQ(m.angular_rate[2], 1 * kDeg);  // r = -gyro z: clockwise is + in NED
  EXPECT_EQ(m.calibration_mag, 3);
  const heading_t& h = r.out.headings.back();
  EXPECT_NEAR(h.heading, kPi / 2, 2e-4);
  EXPECT_NEAR(h.variance, std::pow(2.5 * kDeg, 2), 1e-15);
  EXPECT_EQ(h.reference, heading_t::REFERENCE_MAGNETIC);
  EXPECT_EQ(h.source, heading_t::SOURCE_AHRS);
  EXPECT_EQ(h.device, "bno055@/dev/i2c-1:0x28");
  EXPECT_EQ(n.counter_value("samples"), 49);
  EXPECT_EQ(n.counter_value("bus.errors"), 0);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK);
}

TEST(ImuNode, MissingDeviceIsFaultNamingBusAndAddressAndIsRetried) {
  Rig r;  // nothing at 0x28
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 2 * kUsPerSecond);
  EXPECT_TRUE(r.out.imu.empty());
  EXPECT_EQ(n.counter_value("init.failures"), 3);  // t = 0, 1 s, 2 s
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(r.out.hb.status.find("bno055 on /dev/i2c-1 at 0x28: no answer"), std::string::npos)
      << r.out.hb.status;
  EXPECT_NE(r.out.hb.status.find("ENXIO"), std::string::npos) << r.out.hb.status;
  r.bus.attach(0x28, &r.dev);  // plugged in: found at t = 3 s
  r.run(n, 2 * kUsPerSecond + 20'000, 4 * kUsPerSecond);
  EXPECT_TRUE(n.device_ready());
  EXPECT_EQ(r.out.imu.size(), 49u);  // 3.04 .. 4.0 s
}

// tiller-imu's real transport on a bus that does not exist (no /dev/i2c-N: i2c-dev not loaded):
// no exception, the same FAULT as a missing device naming the bus and ENOENT, retried every
// second; the process keeps running (before: LinuxI2c threw and tiller-imu exited 2).
TEST(ImuNode, MissingBusIsFaultNamingTheBusAndIsRetried) {
  const std::string path = "/nonexistent/i2c-99";
  EXPECT_THROW(i2c::LinuxI2c strict(path), std::runtime_error);  // the ESC driver's choice
  i2c::LinuxI2c bus(path, i2c::LinuxI2c::IfMissing::kRetry);
  EXPECT_FALSE(bus.is_open());
  EXPECT_NE(bus.open_error().find("cannot open I2C bus " + path), std::string::npos);
  EXPECT_NE(bus.open_error().find("modprobe i2c-dev"), std::string::npos) << bus.open_error();
  const std::uint8_t b[2] = {0x3D, 0x00};
  EXPECT_EQ(bus.write(0x28, b, 2), ENOENT);
  Rig r;
  ImuNode n(r.p, bus);
  n.attach(&r.out);
  r.run(n, 0, 2 * kUsPerSecond);
  EXPECT_TRUE(r.out.imu.empty());
  EXPECT_EQ(n.counter_value("init.failures"), 3);  // t = 0, 1 s, 2 s
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(r.out.hb.status.find("bno055 on " + path + " at 0x28: no answer"), std::string::npos)
      << r.out.hb.status;
  EXPECT_NE(r.out.hb.status.find("ENOENT (no such I2C bus"), std::string::npos) << r.out.hb.status;
  EXPECT_NE(r.out.hb.status.find("retrying every 1000 ms"), std::string::npos) << r.out.hb.status;
}

TEST(ImuNode, WrongChipIdIsRefused) {
  Rig r;
  r.dev.chip_id = 0x55;
  r.dev.power_cycle();
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  EXPECT_TRUE(r.out.imu.empty());
  EXPECT_NE(r.out.hb.status.find("CHIP_ID reads 0x55, not 0xa0"), std::string::npos)
      << r.out.hb.status;
}

TEST(ImuNode, ABrownOutIsDetectedAndSetUpAgain) {
  Rig r;
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  const auto before = r.out.imu.size();
  r.dev.power_cycle();  // back in CONFIGMODE, UNIT_SEL 0x80
  r.run(n, 520'000, kUsPerSecond);
  EXPECT_EQ(n.counter_value("device.resets"), 1);
  EXPECT_TRUE(n.device_ready());
  // The tick at 520 ms notices it; 540 ms: probe, CONFIGMODE; 560 ms: units, NDOF; 580 ms:
  // running again.
  EXPECT_EQ(r.out.imu.size(), before + 22u);  // 580 .. 1000 ms
  EXPECT_EQ(r.dev.reg(bno055::kRegOprMode), bno055::kModeNdof);
}

TEST(ImuNode, UncalibratedFusionGivesNoOrientationAndNoHeading) {
  Rig r;
  r.dev.calib_stat = 0x3F;  // system 0, gyro/accel/mag 3 (the magnetic north not found yet)
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  ASSERT_EQ(r.out.imu.size(), 49u);  // rates and specific force still published
  EXPECT_FALSE(r.out.imu.back().orientation_valid);
  EXPECT_EQ(r.out.imu.back().calibration_system, 0);
  EXPECT_TRUE(r.out.headings.empty());
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(r.out.hb.status.find("calibrating"), std::string::npos) << r.out.hb.status;
  r.dev.calib_stat = 0x7F;  // system 1: valid from the next sample
  r.run(n, kUsPerSecond + 20'000, 2 * kUsPerSecond);
  EXPECT_TRUE(r.out.imu.back().orientation_valid);
  EXPECT_EQ(r.out.headings.size(), 50u);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK);
}

TEST(ImuNode, BusErrorsAreRetriedCountedAndLeadToFaultAfterFive) {
  Rig r;
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  r.bus.fail(0x28, EREMOTEIO, 1);  // one failed transaction: the retry succeeds
  r.run(n, 520'000, 600'000);
  EXPECT_EQ(n.counter_value("bus.retries"), 1);
  EXPECT_EQ(n.counter_value("bus.errors"), 0);
  r.bus.fail(0x28, EREMOTEIO, -1);
  r.run(n, 620'000, kUsPerSecond);  // 5 ticks, each failing twice: lost at 700 ms
  EXPECT_FALSE(n.device_ready());
  EXPECT_EQ(n.counter_value("bus.errors"), 5);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);  // the heartbeat at 1 s
  EXPECT_NE(r.out.hb.status.find("5 reads failed in a row: EREMOTEIO"), std::string::npos)
      << r.out.hb.status;
  r.bus.clear_fault(0x28);
  r.run(n, kUsPerSecond + 20'000, 2 * kUsPerSecond);
  EXPECT_TRUE(n.device_ready());
}

TEST(ImuNode, SystemErrorIsFaultNamingSysErr) {
  Rig r;
  r.dev.sys_err = 9;
  r.bus.attach(0x28, &r.dev);
  ImuNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  EXPECT_TRUE(r.out.imu.empty());
  EXPECT_EQ(n.counter_value("device.errors"), 1);  // at 40 ms; set up again at 1.04 s
  EXPECT_NE(r.out.hb.status.find("fusion algorithm configuration error (SYS_ERR 0x09)"),
            std::string::npos)
      << r.out.hb.status;
}

TEST(ImuConfig, StrictLoader) {
  const auto p = load_imu_file(TILLER_SOURCE_DIR "/config/sensors/imu_bno055.yaml");
  EXPECT_EQ(p.address, 0x28);
  EXPECT_EQ(p.mode, bno055::kModeNdof);
  EXPECT_EQ(p.mount.axis, (std::array<int, 3>{1, 0, 2}));
  EXPECT_EQ(p.mount.sign, (std::array<int, 3>{1, 1, -1}));
  EXPECT_FALSE(p.true_north);
  auto error = [](const std::string& text) {
    try {
      load_imu_params(config::Value::parse(text, "imu.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string twice = error("mount:\n  forward: +y\n  right: +y\n  down: -z\n");
  EXPECT_NE(twice.find("imu.yaml:2: mount"), std::string::npos) << twice;
  EXPECT_NE(twice.find("right-handed"), std::string::npos) << twice;
  EXPECT_NE(error("mount:\n  forward: y+\n").find("mount.forward"), std::string::npos);
  EXPECT_NE(error("address: 0x30\n").find("address"), std::string::npos);
  EXPECT_NE(error("rate_hz: 200\n").find("rate_hz"), std::string::npos);
  EXPECT_NE(error("mode: imu\n").find("mode"), std::string::npos);
  EXPECT_NE(error("declination: 3\n").find("unknown key"), std::string::npos);
  const auto t = load_imu_params(config::Value::parse("declination_deg: -4.5\n"));
  EXPECT_TRUE(t.true_north);
  EXPECT_DOUBLE_EQ(t.declination, -4.5 * kDeg);
}

}  // namespace
}  // namespace tiller::sensors
