// Round trips of the sensor messages (GNSS, IMU, heading, pressure, power, leak, vehicle
// status): every field set away from its default comes back bit for bit.
#include <gtest/gtest.h>

#include <tiller/dvl_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/pressure_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include "round_trip.hpp"

namespace tiller {
namespace {
using test::round_trip;

TEST(SensorMessages, GnssFix) {
  gnss_fix_t g{};
  g.utime = 101;
  g.gnss_utime = 1'764'633'600'250'000;
  g.fix_type = gnss_fix_t::FIX_RTK_FIXED;
  g.satellites = 17;
  g.latitude = 59.437123456;
  g.longitude = -10.66123456;
  g.altitude = 42.5;
  g.altitude_msl = 3.25;
  g.position_std[0] = 0.02;
  g.position_std[1] = 0.03;
  g.position_std[2] = 0.05;
  g.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  g.hdop = 0.7;
  g.velocity_valid = true;
  g.speed = 2.25;
  g.course = -1.5;
  g.device = "/dev/ttyACM0";
  const auto r = round_trip(g);
  EXPECT_EQ(r.gnss_utime, g.gnss_utime);
  EXPECT_EQ(r.fix_type, gnss_fix_t::FIX_RTK_FIXED);
  EXPECT_EQ(r.satellites, 17);
  EXPECT_EQ(r.latitude, g.latitude);
  EXPECT_EQ(r.longitude, g.longitude);
  EXPECT_EQ(r.altitude_msl, 3.25);
  EXPECT_EQ(r.position_std[2], 0.05);
  EXPECT_EQ(r.hdop, 0.7);
  EXPECT_TRUE(r.velocity_valid);
  EXPECT_EQ(r.course, -1.5);
  EXPECT_EQ(r.device, g.device);
}

TEST(SensorMessages, ImuAndHeading) {
  imu_t m{};
  m.utime = 102;
  for (int i = 0; i < 3; ++i) {
    m.angular_rate[i] = 0.1 * (i + 1);
    m.specific_force[i] = -3.0 * (i + 1);
  }
  m.orientation_valid = true;
  m.orientation[0] = 0.5;
  m.orientation[1] = -0.5;
  m.orientation[2] = 0.5;
  m.orientation[3] = -0.5;
  for (int i = 0; i < 9; ++i) {
    m.angular_rate_covariance[i] = 1e-6 * i;
    m.specific_force_covariance[i] = 1e-4 * i;
    m.orientation_covariance[i] = 1e-3 * i;
  }
  m.heading_is_magnetic = true;
  m.calibration_system = 3;
  m.calibration_gyro = 2;
  m.calibration_accel = 1;
  m.calibration_mag = -1;
  m.temperature = 31.0;
  const auto r = round_trip(m);
  EXPECT_EQ(r.angular_rate[2], 0.30000000000000004);
  EXPECT_EQ(r.specific_force[1], -6.0);
  EXPECT_EQ(r.orientation[3], -0.5);
  EXPECT_EQ(r.specific_force_covariance[8], 8e-4);
  EXPECT_EQ(r.orientation_covariance[4], 4e-3);
  EXPECT_TRUE(r.heading_is_magnetic);
  EXPECT_EQ(r.calibration_gyro, 2);
  EXPECT_EQ(r.calibration_mag, -1);
  EXPECT_EQ(r.temperature, 31.0);

  heading_t h{};
  h.utime = 103;
  h.heading = -2.5;
  h.variance = 0.003;
  h.reference = heading_t::REFERENCE_TRUE;
  h.source = heading_t::SOURCE_GNSS;
  h.device = "sim";
  const auto rh = round_trip(h);
  EXPECT_EQ(rh.heading, -2.5);
  EXPECT_EQ(rh.variance, 0.003);
  EXPECT_EQ(rh.reference, heading_t::REFERENCE_TRUE);
  EXPECT_EQ(rh.source, heading_t::SOURCE_GNSS);
  EXPECT_EQ(rh.device, "sim");
}

TEST(SensorMessages, PressureAndPower) {
  pressure_t p{};
  p.utime = 104;
  p.pressure = 200'123.5;
  p.temperature = 7.25;
  p.depth = 9.82;
  p.water_density = 1025;
  p.surface_pressure = 101'325;
  p.depth_variance = 1e-4;
  p.sensor = "ms5837-30ba@/dev/i2c-1:0x76";
  const auto rp = round_trip(p);
  EXPECT_EQ(rp.pressure, 200'123.5);
  EXPECT_EQ(rp.temperature, 7.25);
  EXPECT_EQ(rp.depth, 9.82);
  EXPECT_EQ(rp.water_density, 1025);
  EXPECT_EQ(rp.surface_pressure, 101'325);
  EXPECT_EQ(rp.depth_variance, 1e-4);
  EXPECT_EQ(rp.sensor, p.sensor);

  power_t w{};
  w.utime = 105;
  w.voltage = 15.75;
  w.current = -2.5;
  w.power = -39.375;
  w.consumed_charge = 0.125;
  w.consumed_energy = 2.0;
  w.monitor = "ina226@/dev/i2c-1:0x40";
  const auto rw = round_trip(w);
  EXPECT_EQ(rw.voltage, 15.75);
  EXPECT_EQ(rw.current, -2.5);
  EXPECT_EQ(rw.power, -39.375);
  EXPECT_EQ(rw.consumed_charge, 0.125);
  EXPECT_EQ(rw.consumed_energy, 2.0);
  EXPECT_EQ(rw.monitor, w.monitor);
}

TEST(SensorMessages, LeakAndVehicleStatus) {
  leak_t l{};
  l.utime = 106;
  l.n_probes = 3;
  l.names = {"main_tube", "battery", "camera"};
  l.wet = {false, true, true};
  l.readable = {true, true, false};
  l.any_wet = true;
  const auto rl = round_trip(l);
  EXPECT_EQ(rl.names, l.names);
  EXPECT_EQ(rl.wet, l.wet);
  EXPECT_EQ(rl.readable, l.readable);
  EXPECT_TRUE(rl.any_wet);

  vehicle_status_t v{};
  v.utime = 107;
  v.active = +vehicle_status_t::EVENT_GNSS_LOST | +vehicle_status_t::EVENT_GEOFENCE;
  v.latched = vehicle_status_t::EVENT_ALL;
  v.action = vehicle_status_t::ACTION_HOLD;
  v.reason = "GNSS lost for 12.0 s > 10 s";
  const auto rv = round_trip(v);
  EXPECT_EQ(rv.active, v.active);
  EXPECT_EQ(rv.latched, vehicle_status_t::EVENT_ALL);
  EXPECT_EQ(rv.action, vehicle_status_t::ACTION_HOLD);
  EXPECT_EQ(rv.reason, v.reason);
}

TEST(SensorMessages, Dvl) {
  dvl_t d{};
  d.utime = 108;
  d.bottom_lock = true;
  d.velocity[0] = 0.125;
  d.velocity[1] = -0.5;
  d.velocity[2] = 0.0625;
  d.velocity_covariance[0] = 1e-4;
  d.velocity_covariance[4] = 2e-4;
  d.velocity_covariance[8] = 4e-4;
  d.fom = 0.0123;
  d.altitude = 3.25;
  d.beams_valid = 3;
  d.status = 0;
  d.sensor = "dvl-a50@192.168.194.95:16171";
  const auto r = round_trip(d);
  EXPECT_TRUE(r.bottom_lock);
  EXPECT_EQ(r.velocity[1], -0.5);
  EXPECT_EQ(r.velocity_covariance[8], 4e-4);
  EXPECT_EQ(r.fom, 0.0123);
  EXPECT_EQ(r.altitude, 3.25);
  EXPECT_EQ(r.beams_valid, 3);
  EXPECT_EQ(r.sensor, d.sensor);
}

}  // namespace
}  // namespace tiller
