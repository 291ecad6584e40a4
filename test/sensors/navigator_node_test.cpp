// tiller-navigator's node on the fake Navigator (ICM-20602 on FakeSpi, AK09915 on FakeBus): a
// tilted, turned board held still gives the truth's attitude and heading; the declination is
// added; no heading before the filter settles, none without a compass; a missing IMU is a FAULT
// naming the device, and the node keeps running.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <tiller/heartbeat_t.hpp>

#include "ahrs/compass_calibration.hpp"
#include "ahrs/mahony.hpp"
#include "i2c/fake_bus.hpp"
#include "sensors/fake/navigator_models.hpp"
#include "sensors/navigator_node.hpp"
#include "spi/fake_spi.hpp"

namespace {
using namespace tiller;
using namespace tiller::sensors;
constexpr double kDeg = std::numbers::pi / 180.0;

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
    } else if (ch == "TILLER_HEARTBEAT_NAVIGATOR") {
      hb.decode(d, 0, n);
    }
  }
};

struct Rig {
  spi::FakeSpi spi{"/dev/spidev1.0"};
  i2c::FakeBus i2c{"/dev/i2c-1"};
  fake::Icm20602Model imu;
  fake::Ak09915Model compass;
  NavigatorParams p;
  Capture out;
  ahrs::Quat truth;
  // The board held at roll 10, pitch -5, yaw 60 deg in a field of (20, 0, 45) uT NED. Default
  // mount: body forward = chip +y, right = +x, down = -z, so chip = (body y, body x, -body z).
  Rig() {
    truth = ahrs::quat_of_euler(10 * kDeg, -5 * kDeg, 60 * kDeg);
    const auto f = ahrs::to_body(truth, {0, 0, -9.80665});
    const auto m = ahrs::to_body(truth, {20, 0, 45});
    const double fc[3] = {f[1], f[0], -f[2]}, mc[3] = {m[1], m[0], -m[2]};
    for (int i = 0; i < 3; ++i) {
      imu.accel[i] = fc[i];
      imu.gyro[i] = 0;
      compass.field_ut[i] = mc[i];
    }
    spi.attach(&imu);
    i2c.attach(ak09915::kAddress, &compass);
  }
  void run(NavigatorNode& n, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += n.tick_period()) n.tick(t);
  }
};

TEST(NavigatorNode, StillBoardGivesTheTruthsAttitudeAndHeading) {
  Rig r;
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  r.run(n, 0, 1'000'000);
  ASSERT_FALSE(r.out.imu.empty());
  EXPECT_FALSE(r.out.imu.back().orientation_valid);  // settling (2 s)
  EXPECT_TRUE(r.out.headings.empty());
  r.run(n, 1'010'000, 4'000'000);
  const imu_t& m = r.out.imu.back();
  ASSERT_TRUE(m.orientation_valid);
  const ahrs::Quat q{m.orientation[0], m.orientation[1], m.orientation[2], m.orientation[3]};
  // Quantisation: accelerometer 1/4096 g, compass 0.15 uT: well under 0.1 deg.
  EXPECT_LT(ahrs::angle_between(q, r.truth), 0.1 * kDeg);
  EXPECT_NEAR(m.specific_force[2], ahrs::to_body(r.truth, {0, 0, -9.80665})[2], 0.01);
  EXPECT_NEAR(m.temperature, 30.0, 0.01);
  ASSERT_FALSE(r.out.headings.empty());
  EXPECT_NEAR(r.out.headings.back().heading, 60 * kDeg, 0.1 * kDeg);
  EXPECT_EQ(r.out.headings.back().source, heading_t::SOURCE_AHRS);
  EXPECT_EQ(r.out.headings.back().reference, heading_t::REFERENCE_MAGNETIC);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK) << r.out.hb.status;
}

// A newer board's MMC5983MA (compass: mmc5983) at 0x30 instead of the AK09915: the same still
// board gives the same attitude and heading; a chip with another product id is not taken.
TEST(NavigatorNode, TheMmc5983CompassGivesTheSameHeading) {
  Rig r;
  fake::Mmc5983Model mmc;
  for (int i = 0; i < 3; ++i) mmc.field_ut[i] = r.compass.field_ut[i];
  r.i2c.detach(ak09915::kAddress);
  r.i2c.attach(mmc5983::kAddress, &mmc);
  r.p.compass_mmc5983 = true;
  r.p.compass_address = mmc5983::kAddress;
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  r.run(n, 0, 4'000'000);
  ASSERT_TRUE(n.compass_up());
  const imu_t& m = r.out.imu.back();
  ASSERT_TRUE(m.orientation_valid);
  const ahrs::Quat q{m.orientation[0], m.orientation[1], m.orientation[2], m.orientation[3]};
  EXPECT_LT(ahrs::angle_between(q, r.truth), 0.1 * kDeg);  // 6.1 nT per count: finer still
  ASSERT_FALSE(r.out.headings.empty());
  EXPECT_NEAR(r.out.headings.back().heading, 60 * kDeg, 0.1 * kDeg);
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK) << r.out.hb.status;
  EXPECT_GT(mmc.samples, 300);  // continuous mode at 100 Hz
  // Another chip at 0x30: no compass, DEGRADED, the chip named.
  Rig r2;
  fake::Mmc5983Model other;
  other.product_id = 0x12;
  r2.i2c.attach(mmc5983::kAddress, &other);
  r2.p.compass_mmc5983 = true;
  r2.p.compass_address = mmc5983::kAddress;
  NavigatorNode n2(r2.p, r2.spi, r2.i2c);
  n2.attach(&r2.out);
  r2.run(n2, 0, 1'500'000);
  EXPECT_FALSE(n2.compass_up());
  EXPECT_EQ(r2.out.hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(r2.out.hb.status.find("mmc5983 on /dev/i2c-1 at 0x30"), std::string::npos)
      << r2.out.hb.status;
}

TEST(NavigatorNode, DeclinationMakesTheHeadingTrue) {
  Rig r;
  r.p.declination = 3 * kDeg;
  r.p.true_north = true;
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  r.run(n, 0, 3'000'000);
  ASSERT_FALSE(r.out.headings.empty());
  EXPECT_NEAR(r.out.headings.back().heading, 63 * kDeg, 0.1 * kDeg);
  EXPECT_EQ(r.out.headings.back().reference, heading_t::REFERENCE_TRUE);
}

TEST(NavigatorNode, NoCompassNoHeadingButRates) {
  Rig r;
  r.i2c.detach(ak09915::kAddress);
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  r.run(n, 0, 3'000'000);
  ASSERT_FALSE(r.out.imu.empty());
  EXPECT_FALSE(r.out.imu.back().orientation_valid);
  EXPECT_TRUE(r.out.headings.empty());
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(r.out.hb.status.find("ak09915"), std::string::npos) << r.out.hb.status;
}

TEST(NavigatorNode, MissingImuIsAFaultNamingTheDevice) {
  Rig r;
  r.spi.attach(nullptr);
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  r.run(n, 0, 3'000'000);
  EXPECT_TRUE(r.out.imu.empty());
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(r.out.hb.status.find("icm20602 on /dev/spidev1.0"), std::string::npos)
      << r.out.hb.status;
  // Plugged in: set up again on the next retry, samples flow.
  r.spi.attach(&r.imu);
  r.run(n, 3'010'000, 5'000'000);
  EXPECT_FALSE(r.out.imu.empty());
}

// --calibrate-compass's recording: the board turned through attitudes on a spiral over the
// sphere, the chip reading a field distorted by hard iron (12, -7, 4) uT and soft iron (gains
// 1.15, 0.9, 1.0 on the chip's axes). The recorded body-axis samples fit back to that offset in
// body axes (chip (x, y, z) is body (y, x, -z): body (-7, 12, -4) uT) within 0.3 uT, with the
// 0.15 uT quantisation; recording stops at its capacity and the ticks allocate nothing more.
TEST(NavigatorNode, ARecordedRotationFitsTheHardAndSoftIron) {
  Rig r;
  NavigatorNode n(r.p, r.spi, r.i2c);
  n.attach(&r.out);
  n.record_compass(600);
  const double hard[3] = {12, -7, 4}, gain[3] = {1.15, 0.9, 1.0};
  const int k_max = 800;
  for (int k = 0; k < k_max; ++k) {
    // A direction on a spiral from pole to pole: the field as the chip sees it, 50 uT.
    const double zc = -1 + 2.0 * (k + 0.5) / k_max, rho = std::sqrt(1 - zc * zc);
    const double az = k * 2.399963;  // the golden angle
    const double b[3] = {50 * rho * std::cos(az), 50 * rho * std::sin(az), 50 * zc};
    for (int i = 0; i < 3; ++i) r.compass.field_ut[i] = gain[i] * b[i] + hard[i];
    const TimeUs t = static_cast<TimeUs>(k) * n.tick_period();
    n.tick(t);
  }
  ASSERT_EQ(n.recorded().size(), 600u);  // capped at what was reserved
  const ahrs::FitResult f = ahrs::fit_ellipsoid(n.recorded());
  ASSERT_TRUE(f.ok) << f.why;
  EXPECT_NEAR(f.cal.offset[0], -7, 0.3);
  EXPECT_NEAR(f.cal.offset[1], 12, 0.3);
  EXPECT_NEAR(f.cal.offset[2], -4, 0.3);
  EXPECT_LT(f.relative_residual, 0.01);
  std::printf("compass fit from %zu samples: offset (%.2f, %.2f, %.2f) uT, residual %.3f %%\n",
              n.recorded().size(), f.cal.offset[0], f.cal.offset[1], f.cal.offset[2],
              100 * f.relative_residual);
}

}  // namespace
