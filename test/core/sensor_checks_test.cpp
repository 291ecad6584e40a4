// Message checks for the sensor types (core/message_checks.hpp, the "sensors" block): a good
// message of each type passes; each numeric field at both ends of its documented range passes,
// and just beyond either end, NaN and infinity are refused with the field's reason; enums,
// counts and the cross-field rules (depth from pressure, any_wet, latched bits) likewise.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/message_checks.hpp"

namespace tiller::checks {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

template <class Msg>
using Set = std::function<void(Msg&, double)>;

// For one double field with range [lo, hi]: ends pass; beyond, NaN, +-inf give `reason`.
template <class Msg>
void check_range(const Msg& good, const std::string& what, Set<Msg> set, double lo, double hi,
                 const char* reason) {
  const double span = hi - lo;
  struct V {
    double v;
    bool ok;
  };
  for (const V c : {V{lo, true}, V{hi, true}, V{lo - 1e-6 * span, false},
                    V{hi + 1e-6 * span, false}, V{kNan, false}, V{kInf, false}, V{-kInf, false}}) {
    Msg m = good;
    set(m, c.v);
    const char* got = check(m);
    EXPECT_STREQ(got ? got : "(ok)", c.ok ? "(ok)" : reason)
        << Msg::getTypeName() << "." << what << " = " << c.v;
  }
}

template <class Msg>
void expect_reason(const Msg& good, const std::string& what, std::function<void(Msg&)> perturb,
                   const char* reason) {
  Msg m = good;
  perturb(m);
  const char* got = check(m);
  EXPECT_STREQ(got ? got : "(ok)", reason ? reason : "(ok)") << Msg::getTypeName() << ": " << what;
}

gnss_fix_t good_fix() {
  gnss_fix_t g{};
  g.utime = 1'000'000;
  g.gnss_utime = 1'764'633'600'000'000;
  g.fix_type = gnss_fix_t::FIX_3D;
  g.satellites = 9;
  g.latitude = 59.4371;
  g.longitude = 10.6612;
  g.altitude = 40.2;
  g.altitude_msl = 2.1;
  g.position_std[0] = g.position_std[1] = 1.2;
  g.position_std[2] = 2.5;
  g.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  g.hdop = 0.9;
  g.velocity_valid = true;
  g.speed = 1.5;
  g.course = -2.0;
  g.device = "/dev/ttyACM0";
  return g;
}

TEST(SensorChecks, GnssFix) {
  const auto g = good_fix();
  EXPECT_EQ(check(g), nullptr);
  using M = gnss_fix_t;
  check_range<M>(
      g, "latitude", [](M& m, double v) { m.latitude = v; }, -90, 90, "latitude.range");
  check_range<M>(
      g, "longitude", [](M& m, double v) { m.longitude = v; }, -180, 180, "longitude.range");
  check_range<M>(
      g, "altitude", [](M& m, double v) { m.altitude = v; }, -1e4, 1e5, "altitude.range");
  check_range<M>(
      g, "altitude_msl", [](M& m, double v) { m.altitude_msl = v; }, -1e4, 1e5, "altitude.range");
  for (int i = 0; i < 3; ++i)
    check_range<M>(
        g, "position_std", [i](M& m, double v) { m.position_std[i] = v; }, 0, 1e5,
        "position_std.range");
  check_range<M>(
      g, "hdop", [](M& m, double v) { m.hdop = v; }, 0, 100, "hdop.range");
  check_range<M>(
      g, "speed", [](M& m, double v) { m.speed = v; }, 0, 300, "speed.range");
  expect_reason<M>(
      g, "course pi", [](M& m) { m.course = kPi; }, nullptr);
  expect_reason<M>(
      g, "course -pi", [](M& m) { m.course = -kPi; }, "course.range");
  expect_reason<M>(
      g, "course NaN", [](M& m) { m.course = kNan; }, "course.range");
  expect_reason<M>(
      g, "course 4", [](M& m) { m.course = 4; }, "course.range");
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
  expect_reason<M>(
      g, "gnss_utime -1", [](M& m) { m.gnss_utime = -1; }, "utime.range");
  expect_reason<M>(
      g, "fix 6", [](M& m) { m.fix_type = M::FIX_DEAD_RECKONING; }, nullptr);
  expect_reason<M>(
      g, "fix 7", [](M& m) { m.fix_type = 7; }, "fix_type.unknown");
  expect_reason<M>(
      g, "fix -1", [](M& m) { m.fix_type = -1; }, "fix_type.unknown");
  expect_reason<M>(
      g, "sats -1", [](M& m) { m.satellites = -1; }, nullptr);
  expect_reason<M>(
      g, "sats 255", [](M& m) { m.satellites = 255; }, nullptr);
  expect_reason<M>(
      g, "sats 256", [](M& m) { m.satellites = 256; }, "satellites.range");
  expect_reason<M>(
      g, "sats -2", [](M& m) { m.satellites = -2; }, "satellites.range");
  expect_reason<M>(
      g, "accuracy 3", [](M& m) { m.accuracy_source = 3; }, "accuracy_source.unknown");
  // A no-fix message as a driver sends it: zeros, not NaN.
  gnss_fix_t none{};
  EXPECT_EQ(check(none), nullptr);
}

imu_t good_imu() {
  imu_t g{};
  g.utime = 5;
  g.angular_rate[2] = 0.3;
  g.specific_force[2] = -9.81;
  g.orientation_valid = true;
  g.orientation[0] = std::cos(0.25);
  g.orientation[3] = std::sin(0.25);
  g.angular_rate_covariance[0] = g.angular_rate_covariance[4] = g.angular_rate_covariance[8] = 1e-6;
  g.heading_is_magnetic = true;
  g.calibration_system = 3;
  g.calibration_gyro = 3;
  g.calibration_accel = 1;
  g.calibration_mag = 0;
  g.temperature = 24;
  return g;
}

TEST(SensorChecks, Imu) {
  const auto g = good_imu();
  EXPECT_EQ(check(g), nullptr);
  using M = imu_t;
  for (int i = 0; i < 3; ++i) {
    check_range<M>(
        g, "angular_rate", [i](M& m, double v) { m.angular_rate[i] = v; }, -40, 40,
        "angular_rate.range");
    check_range<M>(
        g, "specific_force", [i](M& m, double v) { m.specific_force[i] = v; }, -400, 400,
        "specific_force.range");
  }
  check_range<M>(
      g, "temperature", [](M& m, double v) { m.temperature = v; }, -60, 150, "temperature.range");
  expect_reason<M>(
      g, "q NaN", [](M& m) { m.orientation[2] = kNan; }, "orientation.nan");
  expect_reason<M>(
      g, "q NaN, not valid",
      [](M& m) {
        m.orientation_valid = false;
        m.orientation[2] = kNan;
      },
      "orientation.nan");
  expect_reason<M>(
      g, "q norm 1.02", [](M& m) { m.orientation[0] *= 1.02, m.orientation[3] *= 1.02; },
      "orientation.norm");
  expect_reason<M>(
      g, "q norm 1.009", [](M& m) { m.orientation[0] *= 1.009, m.orientation[3] *= 1.009; },
      nullptr);
  expect_reason<M>(
      g, "q zero", [](M& m) { m.orientation[0] = m.orientation[3] = 0; }, "orientation.norm");
  expect_reason<M>(
      g, "q zero, not valid",
      [](M& m) {
        m.orientation_valid = false;
        m.orientation[0] = m.orientation[3] = 0;
      },
      nullptr);
  expect_reason<M>(
      g, "rate var < 0", [](M& m) { m.angular_rate_covariance[4] = -1e-9; },
      "angular_rate_cov.range");
  expect_reason<M>(
      g, "rate cov off-diagonal < 0", [](M& m) { m.angular_rate_covariance[1] = -1e-7; }, nullptr);
  expect_reason<M>(
      g, "force cov NaN", [](M& m) { m.specific_force_covariance[3] = kNan; },
      "specific_force_cov.range");
  expect_reason<M>(
      g, "orientation var < 0", [](M& m) { m.orientation_covariance[8] = -1; },
      "orientation_cov.range");
  expect_reason<M>(
      g, "calib -1", [](M& m) { m.calibration_mag = -1; }, nullptr);
  expect_reason<M>(
      g, "calib 4", [](M& m) { m.calibration_gyro = 4; }, "calibration.range");
  expect_reason<M>(
      g, "calib -2", [](M& m) { m.calibration_system = -2; }, "calibration.range");
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

TEST(SensorChecks, Heading) {
  heading_t g{};
  g.utime = 1;
  g.heading = 1.0;
  g.variance = 0.01;
  g.reference = heading_t::REFERENCE_MAGNETIC;
  g.source = heading_t::SOURCE_AHRS;
  EXPECT_EQ(check(g), nullptr);
  using M = heading_t;
  check_range<M>(
      g, "variance", [](M& m, double v) { m.variance = v; }, 0, 10, "variance.range");
  expect_reason<M>(
      g, "pi", [](M& m) { m.heading = kPi; }, nullptr);
  expect_reason<M>(
      g, "-pi", [](M& m) { m.heading = -kPi; }, "heading.range");
  expect_reason<M>(
      g, "NaN", [](M& m) { m.heading = kNan; }, "heading.range");
  expect_reason<M>(
      g, "reference 2", [](M& m) { m.reference = 2; }, "reference.unknown");
  expect_reason<M>(
      g, "source sim", [](M& m) { m.source = M::SOURCE_SIM; }, nullptr);
  expect_reason<M>(
      g, "source 4", [](M& m) { m.source = 4; }, "source.unknown");
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

// A pressure message whose depth follows from its other fields (as the drivers make them).
void set_depth(pressure_t& m) {
  m.depth = (m.pressure - m.surface_pressure) / (m.water_density * 9.80665);
}

TEST(SensorChecks, Pressure) {
  pressure_t g{};
  g.utime = 1;
  g.pressure = 200'000;
  g.temperature = 12.5;
  g.water_density = 1025;
  g.surface_pressure = 101'325;
  set_depth(g);  // 98675 Pa / (1025 kg/m^3 * 9.80665 m/s^2) = 9.81663 m
  EXPECT_NEAR(g.depth, 9.81663, 1e-5);
  EXPECT_EQ(check(g), nullptr);
  using M = pressure_t;
  check_range<M>(
      g, "temperature", [](M& m, double v) { m.temperature = v; }, -40, 125, "temperature.range");
  check_range<M>(
      g, "depth_variance", [](M& m, double v) { m.depth_variance = v; }, 0, 1e4,
      "depth_variance.range");
  // Fields that move depth: keep depth consistent so that only the range is tested.
  check_range<M>(
      g, "pressure", [](M& m, double v) { m.pressure = v, m.surface_pressure = 1e5, set_depth(m); },
      0, 2e7, "pressure.range");
  check_range<M>(
      g, "water_density", [](M& m, double v) { m.water_density = v, set_depth(m); }, 900, 1100,
      "water_density.range");
  check_range<M>(
      g, "surface_pressure", [](M& m, double v) { m.surface_pressure = v, set_depth(m); }, 5e4,
      1.2e5, "surface_pressure.range");
  expect_reason<M>(
      g, "depth NaN", [](M& m) { m.depth = kNan; }, "depth.range");
  expect_reason<M>(
      g, "depth 2001 m",
      [](M& m) {
        m.water_density = 900;
        m.pressure = 101'325 + 2001 * 900 * 9.80665;
        set_depth(m);
      },
      "depth.range");
  expect_reason<M>(
      g, "depth off by 2 mm", [](M& m) { m.depth += 0.002; }, "depth.inconsistent");
  expect_reason<M>(
      g, "depth off by 0.5 mm", [](M& m) { m.depth += 0.0005; }, nullptr);
  expect_reason<M>(
      g, "in air, above the surface",
      [](M& m) {
        m.pressure = 101'000;
        set_depth(m);
      },
      nullptr);
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

TEST(SensorChecks, Power) {
  power_t g{};
  g.utime = 1;
  g.voltage = 15.8;
  g.current = 12.0;
  g.power = 189.6;
  g.consumed_charge = 1.25;
  g.consumed_energy = 19.9;
  EXPECT_EQ(check(g), nullptr);
  using M = power_t;
  check_range<M>(
      g, "voltage", [](M& m, double v) { m.voltage = v; }, 0, 100, "voltage.range");
  check_range<M>(
      g, "current", [](M& m, double v) { m.current = v; }, -1000, 1000, "current.range");
  check_range<M>(
      g, "power", [](M& m, double v) { m.power = v; }, -1e5, 1e5, "power.range");
  check_range<M>(
      g, "consumed_charge", [](M& m, double v) { m.consumed_charge = v; }, -1e4, 1e4,
      "consumed_charge.range");
  check_range<M>(
      g, "consumed_energy", [](M& m, double v) { m.consumed_energy = v; }, -1e6, 1e6,
      "consumed_energy.range");
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

TEST(SensorChecks, Leak) {
  leak_t g{};
  g.utime = 1;
  g.n_probes = 2;
  g.names = {"main_tube", "battery_tube"};
  g.wet = {false, true};
  g.readable = {true, true};
  g.any_wet = true;
  EXPECT_EQ(check(g), nullptr);
  using M = leak_t;
  expect_reason<M>(
      g, "dry",
      [](M& m) {
        m.wet = {false, false}, m.any_wet = false;
      },
      nullptr);
  expect_reason<M>(
      g, "any_wet false with a wet probe", [](M& m) { m.any_wet = false; }, "any_wet.inconsistent");
  expect_reason<M>(
      g, "any_wet true, all dry",
      [](M& m) {
        m.wet = {false, false};
      },
      "any_wet.inconsistent");
  expect_reason<M>(
      g, "unreadable reads dry", [](M& m) { m.readable[0] = false; }, "wet.unreadable");
  expect_reason<M>(
      g, "unreadable reads wet", [](M& m) { m.readable[0] = false, m.wet[0] = true; }, nullptr);
  expect_reason<M>(
      g, "n 33", [](M& m) { m.n_probes = 33; }, "n_probes.range");
  expect_reason<M>(
      g, "n -1", [](M& m) { m.n_probes = -1; }, "n_probes.range");
  expect_reason<M>(
      g, "n 3 with 2 entries", [](M& m) { m.n_probes = 3; }, "probes.size");
  expect_reason<M>(
      g, "no probes",
      [](M& m) {
        m.n_probes = 0;
        m.any_wet = false;
      },
      nullptr);
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

TEST(SensorChecks, Dvl) {
  dvl_t g{};
  g.utime = 1;
  g.bottom_lock = true;
  g.velocity[0] = 0.3;
  g.velocity_covariance[0] = g.velocity_covariance[4] = g.velocity_covariance[8] = 1e-4;
  g.velocity_covariance[1] = g.velocity_covariance[3] = 2e-5;
  g.fom = 0.01;
  g.altitude = 4.2;
  g.beams_valid = 4;
  EXPECT_EQ(check(g), nullptr);
  using M = dvl_t;
  for (int i = 0; i < 3; ++i)
    check_range<M>(
        g, "velocity", [i](M& m, double v) { m.velocity[i] = v; }, -20, 20, "velocity.range");
  check_range<M>(
      g, "velocity_covariance[4]", [](M& m, double v) { m.velocity_covariance[4] = v; }, 0, 100,
      "velocity_covariance.range");
  check_range<M>(
      g, "fom", [](M& m, double v) { m.fom = v; }, 0, 100, "fom.range");
  check_range<M>(
      g, "altitude", [](M& m, double v) { m.altitude = v; }, 0, 1e3, "altitude.range");
  expect_reason<M>(
      g, "altitude -1 (none)", [](M& m) { m.altitude = -1; }, nullptr);
  expect_reason<M>(
      g, "altitude -0.5", [](M& m) { m.altitude = -0.5; }, "altitude.range");
  expect_reason<M>(
      g, "asymmetric covariance", [](M& m) { m.velocity_covariance[3] = 0; },
      "velocity_covariance.asymmetric");
  expect_reason<M>(
      g, "off-diagonal NaN", [](M& m) { m.velocity_covariance[5] = kNan; },
      "velocity_covariance.range");
  expect_reason<M>(
      g, "beams 5", [](M& m) { m.beams_valid = 5; }, "beams_valid.range");
  expect_reason<M>(
      g, "beams -1 (not reported)", [](M& m) { m.beams_valid = -1; }, nullptr);
  expect_reason<M>(
      g, "velocity without lock", [](M& m) { m.bottom_lock = false; }, "velocity.unlocked");
  expect_reason<M>(
      g, "no lock, zero velocity",
      [](M& m) {
        m.bottom_lock = false;
        m.velocity[0] = 0;
        m.altitude = -1;
      },
      nullptr);
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

TEST(SensorChecks, VehicleStatus) {
  using M = vehicle_status_t;
  M g{};
  g.utime = 1;
  g.active = M::EVENT_LEAK;
  g.latched = +M::EVENT_LEAK | +M::EVENT_BATTERY_WARN;
  g.action = M::ACTION_SURFACE;
  g.reason = "leak: main_tube";
  EXPECT_EQ(check(g), nullptr);
  EXPECT_EQ(M::EVENT_ALL, +M::EVENT_BATTERY_WARN | +M::EVENT_BATTERY_CRITICAL | +M::EVENT_LEAK |
                              +M::EVENT_GNSS_LOST | +M::EVENT_GEOFENCE | +M::EVENT_DEPTH_LIMIT);
  expect_reason<M>(
      g, "all events", [](M& m) { m.active = m.latched = M::EVENT_ALL; }, nullptr);
  expect_reason<M>(
      g, "unknown active bit", [](M& m) { m.active = 64, m.latched = 64 | 4; }, "active.unknown");
  expect_reason<M>(
      g, "negative active", [](M& m) { m.active = -1; }, "active.unknown");
  expect_reason<M>(
      g, "unknown latched bit", [](M& m) { m.latched = 128 | 4; }, "latched.unknown");
  expect_reason<M>(
      g, "active not latched", [](M& m) { m.latched = M::EVENT_BATTERY_WARN; },
      "latched.inconsistent");
  expect_reason<M>(
      g, "action disarm", [](M& m) { m.action = M::ACTION_DISARM; }, nullptr);
  expect_reason<M>(
      g, "action rise", [](M& m) { m.action = M::ACTION_RISE; }, nullptr);
  expect_reason<M>(
      g, "action 8", [](M& m) { m.action = 8; }, "action.unknown");
  expect_reason<M>(
      g, "action -1", [](M& m) { m.action = -1; }, "action.unknown");
  expect_reason<M>(
      g, "utime -1", [](M& m) { m.utime = -1; }, "utime.range");
}

}  // namespace
}  // namespace tiller::checks
