// The simulated sensors (lib/sim/sensor_models.hpp, sensor_suite.hpp, nmea.hpp): NMEA text and
// checksums against the classic published GGA, the noise statistics the config promises (CEP,
// standard deviations), hand-computed specific force, battery and pressure, latency, dropouts,
// outages, leaks, determinism by seed, the sensors file's errors, and tiller-sim's odometry
// choice. Every message passes checks::check.
#include <gtest/gtest.h>

#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/LocalCartesian.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/nmea.hpp"
#include "sim/sensor_suite.hpp"
#include "sim/sim_node.hpp"

namespace tiller::sim {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

TEST(Nmea, ChecksumOfThePublishedGgaExampleIs47) {
  // The GGA example every NMEA guide quotes (e.g. gpsd's NMEA.html): "...,46.9,M,,*47".
  EXPECT_EQ(nmea::checksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), 0x47);
  // And a sentence of the hand-written test data gpsd already accepts (test/data/gnss).
  EXPECT_EQ(nmea::checksum("GPGGA,120000.00,5926.2200,N,01039.6720,E,1,09,0.9,12.3,M,39.8,M,,"),
            0x5D);
}

nmea::Fix example_fix() {
  nmea::Fix f;
  f.utc_us = (12 * 3600 + 35 * 60 + 19) * kUsPerSecond + 250'000;  // 1970-01-01 12:35:19.25
  f.valid = true;
  f.latitude_deg = 48 + 7.038 / 60;
  f.longitude_deg = 11 + 31.0 / 60;
  f.altitude_msl_m = 545.4;
  f.geoid_separation_m = 46.9;
  f.satellites = 8;
  f.hdop = 0.9;
  f.vdop = 1.2;
  f.pdop = 1.5;
  f.speed_m_s = 1852.0 / 3600.0 * 22.4;  // 22.4 kn
  f.course_rad = -M_PI / 2;              // 270 deg true
  f.std_north_m = 1.5;
  f.std_east_m = 1.2;
  f.std_up_m = 2.8;
  return f;
}

std::string checked(const char* buf, std::size_t n) {
  const std::string s(buf, n);
  EXPECT_EQ(s.substr(s.size() - 2), "\r\n");
  const auto star = s.find('*');
  EXPECT_NE(star, std::string::npos);
  char hex[3];
  std::snprintf(hex, sizeof hex, "%02X", nmea::checksum(s.substr(1, star - 1)));
  EXPECT_EQ(s.substr(star + 1, 2), hex) << s;
  return s.substr(0, star);
}

TEST(Nmea, SentencesCarryTheFixInTheirFields) {
  const nmea::Fix f = example_fix();
  char b[256];
  EXPECT_EQ(checked(b, nmea::gga(f, b, sizeof b)),
            "$GPGGA,123519.25,4807.0380000,N,01131.0000000,E,1,08,0.9,545.400,M,46.900,M,,");
  EXPECT_EQ(checked(b, nmea::gsa(f, b, sizeof b)),
            "$GPGSA,A,3,01,03,05,07,09,11,13,15,,,,,1.5,0.9,1.2");
  const std::size_t gsv_n = nmea::gsv(f, b, sizeof b);  // 8 satellites: two sentences
  const std::string gsv(b, gsv_n);
  const auto second = gsv.find("$GPGSV,2,2");
  ASSERT_NE(second, std::string::npos) << gsv;
  EXPECT_EQ(checked(b, second),
            "$GPGSV,2,1,08,01,15,000,38,03,52,097,39,05,19,194,40,07,56,291,41");
  EXPECT_EQ(checked(b + second, gsv_n - second),
            "$GPGSV,2,2,08,09,23,028,42,11,60,125,43,13,27,222,44,15,64,319,38");
  EXPECT_EQ(checked(b, nmea::gst(f, b, sizeof b)),
            "$GPGST,123519.25,1.921,1.500,1.200,0.0,1.500,1.200,2.800");
  EXPECT_EQ(checked(b, nmea::rmc(f, b, sizeof b)),
            "$GPRMC,123519.25,A,4807.0380000,N,01131.0000000,E,22.400,270.00,010170,,,A");
  // South and west; a minute that rounds up to 60 carries into the degrees.
  nmea::Fix s = f;
  s.latitude_deg = -(33 + 51.408 / 60);
  s.longitude_deg = -(151 + 59.99999999 / 60);
  const std::string g = checked(b, nmea::gga(s, b, sizeof b));
  EXPECT_NE(g.find(",3351.4080000,S,15200.0000000,W,"), std::string::npos) << g;
  // No fix: quality 0, status V, empty position, no GST in the epoch.
  nmea::Fix none = f;
  none.valid = false;
  EXPECT_EQ(checked(b, nmea::gga(none, b, sizeof b)), "$GPGGA,123519.25,,,,,0,00,,,M,,M,,");
  EXPECT_EQ(checked(b, nmea::rmc(none, b, sizeof b)), "$GPRMC,123519.25,V,,,,,,,010170,,,N");
  char e[nmea::kMaxEpochBytes];
  const std::string epoch(e, nmea::epoch(none, e, sizeof e));
  EXPECT_EQ(epoch.find("GST"), std::string::npos);
  EXPECT_NE(epoch.find("$GPGSV,1,1,00*"), std::string::npos) << epoch;
  EXPECT_NE(epoch.find("$GPRMC"), std::string::npos);
  EXPECT_EQ(nmea::gga(f, b, 20), 0u);  // too small: nothing usable
}

TrueState still(double north = 0, double east = 0, double yaw = 0) {
  TrueState s;
  s.eta << north, east, 0, 0, 0, yaw;
  return s;
}

TEST(GnssModel, ErrorsHaveTheConfiguredCepAndTheFixIsTheDatumsWgs84) {
  GnssModelParams p;  // 2.5 m CEP, 0.2 m bias of 120 s
  GnssModel m(p, 7);
  GeographicLib::LocalCartesian lc(p.datum_latitude_deg, p.datum_longitude_deg, p.datum_altitude_m,
                                   GeographicLib::Geocentric::WGS84());
  const TrueState s = still(120.0, -80.0);
  std::vector<double> radial;
  double sn = 0, sn2 = 0;
  const int n = 40'000;
  gnss_fix_t f{};
  for (int k = 0; k < n; ++k) {
    m.step_bias(0.2);
    m.sample(TimeUs{k} * 200'000, s, true, f);
    ASSERT_EQ(checks::check(f), nullptr);
    double e = 0, no = 0, u = 0;
    lc.Forward(f.latitude, f.longitude, f.altitude, e, no, u);
    ASSERT_NEAR(no, m.last_ned().x(), 1e-6);  // WGS84 back to NED: GeographicLib both ways
    ASSERT_NEAR(e, m.last_ned().y(), 1e-6);
    ASSERT_NEAR(-u, m.last_ned().z(), 1e-6);
    radial.push_back(std::hypot(no - 120.0, e + 80.0));
    sn += no - 120.0;
    sn2 += (no - 120.0) * (no - 120.0);
  }
  std::nth_element(radial.begin(), radial.begin() + n / 2, radial.end());
  EXPECT_NEAR(radial[n / 2], 2.5, 0.06);  // CEP: the median radial error
  const double mean = sn / n, sd = std::sqrt(sn2 / n - mean * mean);
  EXPECT_NEAR(sd, 2.5 / 1.1774, 0.05);
  EXPECT_LT(std::abs(mean), 0.1);
  EXPECT_EQ(f.fix_type, gnss_fix_t::FIX_3D);
  EXPECT_NEAR(f.position_std[0], 2.5 / 1.1774, 1e-3);
  EXPECT_EQ(f.accuracy_source, gnss_fix_t::ACCURACY_RECEIVER);
  m.sample(0, s, false, f);  // an outage: no fix, zeros, still valid by the checks
  EXPECT_EQ(f.fix_type, gnss_fix_t::FIX_NONE);
  EXPECT_EQ(f.latitude, 0.0);
  EXPECT_EQ(checks::check(f), nullptr);
}

TEST(ImuModel, LevelAtRestReadsMinusGAndATurnReadsItsCentripetalAcceleration) {
  ImuModelParams p;
  p.gyro_std_rad_s = p.accel_std_m_s2 = p.roll_pitch_std_rad = p.yaw_std_rad = 0;
  p.gyro_bias = p.accel_bias = p.roll_pitch_bias = p.yaw_bias = BiasParams{};
  ImuModel m(p, 1);
  imu_t o{};
  m.sample(10, still(0, 0, M_PI / 2), o);
  EXPECT_EQ(checks::check(o), nullptr);
  EXPECT_NEAR(o.specific_force[2], -kGravity, 1e-12);
  EXPECT_NEAR(o.specific_force[0], 0.0, 1e-12);
  // Yaw 90 deg: q = [cos 45, 0, 0, sin 45].
  EXPECT_NEAR(o.orientation[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(o.orientation[3], std::sqrt(0.5), 1e-12);
  // A steady turn, u = 2 m/s, r = 0.1 rad/s: omega x v = [0, r u, 0] = 0.2 m/s^2 to starboard.
  TrueState turn = still();
  turn.nu << 2, 0, 0, 0, 0, 0.1;
  turn.accel_body = turn.nu.tail<3>().cross(turn.nu.head<3>());
  m.sample(20, turn, o);
  EXPECT_NEAR(o.specific_force[1], 0.2, 1e-12);
  EXPECT_NEAR(o.angular_rate[2], 0.1, 1e-12);
  // Pitched up 10 deg at rest: gravity shows on the x axis, +g sin(10 deg).
  TrueState pitched = still();
  pitched.eta[4] = 10 * M_PI / 180;
  m.sample(30, pitched, o);
  EXPECT_NEAR(o.specific_force[0], kGravity * std::sin(10 * M_PI / 180), 1e-12);
}

TEST(BatteryModel, LoadSagsTheVoltageAsItsClosedFormSaysAndDrawsCharge) {
  BatteryModelParams p;  // 16.8 V full, 13.2 V empty, 18 Ah, 0.03 ohm, 15 W, 1.1 W/N^1.5
  BatteryModel b(p, 1);
  const double thrust[2] = {50, -50};
  TrueState s = still();
  s.thrust = thrust;
  s.n_thrusters = 2;
  const double load = 15 + 2 * 1.1 * std::pow(50.0, 1.5);  // 792.8 W
  EXPECT_NEAR(b.load_w(s), load, 1e-9);
  b.step(1.0, s);
  const double i = (16.8 - std::sqrt(16.8 * 16.8 - 4 * 0.03 * load)) / (2 * 0.03);
  EXPECT_NEAR(b.current(), i, 1e-9);  // 52.0 A
  EXPECT_NEAR(b.current(), 52.02, 0.01);
  EXPECT_NEAR(b.voltage() * b.current(), load, 1e-6);
  EXPECT_NEAR(b.consumed_ah(), i / 3600, 1e-12);
  EXPECT_NEAR(b.open_circuit_v(9.0), 15.0, 1e-12);  // half drawn: half way, linear
  for (int k = 0; k < 600; ++k) b.step(1.0, s);     // 10 minutes at full thrust
  EXPECT_LT(b.voltage(), 15.239 - 0.5);
  power_t o{};
  b.sample(5, o);
  EXPECT_EQ(checks::check(o), nullptr);
  EXPECT_GT(o.consumed_charge, 8.0);
}

TEST(PressureModel, TenMetresOfSeaWaterAndTheDepthTheContractComputes) {
  PressureModelParams p;
  p.std_pa = 0;
  PressureModel m(p, 1);
  TrueState s = still();
  s.eta[2] = 10;
  pressure_t o{};
  m.sample(1, s, o);
  EXPECT_NEAR(o.pressure, 101325 + 1025 * 9.80665 * 10, 1e-6);  // 201843.16 Pa
  EXPECT_NEAR(o.depth, 10.0, 1e-9);
  EXPECT_EQ(checks::check(o), nullptr);
}

SensorParams file(const std::string& name, TimeUs step = 10'000) {
  return load_sensor_file(kSrc + "/config/sim/" + name, step);
}

struct Log {
  std::map<std::string, int> count;
  std::vector<std::pair<TimeUs, TimeUs>> imu_times;  // (published at, utime)
  std::vector<gnss_fix_t> fixes;
  std::vector<leak_t> leaks;
  std::string bytes;  // every message encoded, for bit-for-bit comparisons
  template <class M>
  void add(const char* ch, const M& m, TimeUs now) {
    ++count[ch];
    EXPECT_EQ(checks::check(m), nullptr) << ch;
    std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    bytes.append(b.begin(), b.end());
    if constexpr (std::is_same_v<M, imu_t>) imu_times.emplace_back(now, m.utime);
    if constexpr (std::is_same_v<M, gnss_fix_t>) fixes.push_back(m);
    if constexpr (std::is_same_v<M, leak_t>) leaks.push_back(m);
  }
};

Log run(const SensorParams& p, std::uint64_t seed, double seconds) {
  SensorSuite suite(p, seed);
  Log log;
  TrueState s = still();
  double th[2] = {20, 20};
  s.thrust = th;
  s.n_thrusters = 2;
  for (TimeUs t = 10'000; t <= from_seconds(seconds); t += 10'000) {
    s.eta[0] = 0.5 * to_seconds(t);
    suite.step(t, 0.01, s);
    suite.release(t, [&](const char* ch, const auto& m) { log.add(ch, m, t); });
  }
  return log;
}

TEST(SensorSuite, RatesLatencyOutagesAndLeaksFromTheUsvFileDeterministicBySeed) {
  SensorParams p = file("sensors/usv.yaml");
  p.imu_timing.latency_us = 30'000;
  p.gnss_outages.push_back({from_seconds(4), from_seconds(6)});
  p.leak.wet_after_s = 5;
  const Log a = run(p, 3, 10.0);
  EXPECT_EQ(a.count.at(channels::kImu), 997);  // 100 Hz for 10 s, the last 3 still in flight
  EXPECT_EQ(a.count.at(channels::kGnss), 49);  // 5 Hz from 0.2 s; the one of 10.0 s in flight
  EXPECT_EQ(a.count.at(channels::kHeading), 100);
  EXPECT_EQ(a.count.at(channels::kPower), 100);
  EXPECT_EQ(a.count.at(channels::kLeak), 10);
  EXPECT_EQ(a.count.count(channels::kPressure), 0u);  // off on a surface boat
  for (const auto& [at, utime] : a.imu_times) EXPECT_EQ(at - utime, 30'000);
  int none = 0;
  for (const auto& f : a.fixes) {
    const bool out = f.gnss_utime >= 4'000'000 && f.gnss_utime < 6'000'000;
    EXPECT_EQ(f.fix_type == gnss_fix_t::FIX_NONE, out) << f.gnss_utime;
    none += out;
    EXPECT_EQ(f.utime - f.gnss_utime, 100'000);  // reached the host after the latency
  }
  EXPECT_EQ(none, 10);
  for (const auto& l : a.leaks) EXPECT_EQ(l.any_wet, l.utime >= 5'000'000) << l.utime;
  EXPECT_EQ(a.leaks.back().names[0], "hull");
  EXPECT_EQ(run(p, 3, 10.0).bytes, a.bytes);  // same seed: bit for bit
  EXPECT_NE(run(p, 4, 10.0).bytes, a.bytes);
}

TEST(SensorSuite, DropoutsLoseAboutTheirShareAndAreCounted) {
  SensorParams p = file("sensors/rov.yaml");
  p.imu_timing.dropout_probability = 0.3;
  SensorSuite suite(p, 11);
  std::int64_t dropped[6] = {};
  suite.set_drop_counters(&dropped[0], &dropped[1], &dropped[2], &dropped[3], &dropped[4],
                          &dropped[5]);
  int got = 0, depth = 0;
  TrueState s = still();
  s.eta[2] = 3.0;
  for (TimeUs t = 10'000; t <= 100 * kUsPerSecond; t += 10'000) {
    suite.step(t, 0.01, s);
    suite.release(t, [&](const char* ch, const auto& m) {
      got += std::string(ch) == channels::kImu;
      if constexpr (std::is_same_v<std::decay_t<decltype(m)>, pressure_t>) {
        EXPECT_NEAR(m.depth, 3.0, 0.05);  // 20 Pa white + 50 Pa bias: a few mm
        ++depth;
      }
    });
  }
  EXPECT_EQ(got + dropped[1], 10'000);
  EXPECT_NEAR(dropped[1] / 10'000.0, 0.3, 0.015);
  EXPECT_EQ(dropped[0], 0);
  EXPECT_GT(depth, 990);
}

TEST(SensorConfig, ErrorsNameTheFileTheKeyAndTheExpectation) {
  auto error_of = [](const std::string& text) {
    try {
      const auto root = config::Value::parse(text, "s.yaml");
      load_sensor_params(root, 10'000);
      root.check_all_used();
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string datum = "datum: {latitude_deg: 59, longitude_deg: 10, altitude_m: 0}\n";
  EXPECT_NE(error_of(datum + "imu: {enabled: true, rate_hz: 33}").find("imu.rate_hz"),
            std::string::npos);
  EXPECT_NE(error_of("gnss: {enabled: true}").find("datum: missing"), std::string::npos)
      << error_of("gnss: {enabled: true}");
  EXPECT_NE(error_of(datum + "gnss: {enabled: true, horizontal_cep_m: 1, horizontal_bias: "
                             "{std_m: 1}}")
                .find("gnss.horizontal_bias: expected a std_m at most"),
            std::string::npos);
  EXPECT_NE(error_of("leak: {enabled: true, probs: [a]}").find("leak.probs: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("power: {enabled: true, full_v: 12, empty_v: 13}").find("power.empty_v"),
            std::string::npos);
  EXPECT_NE(error_of("pressure: {enabled: true, water: custom}").find("pressure.water_density"),
            std::string::npos);
  EXPECT_NE(error_of(datum + "gnss: {enabled: true, output: serial}").find("gnss.output"),
            std::string::npos);
  EXPECT_EQ(error_of(datum + "gnss: {enabled: true, latency_s: 2.8}"), "no error");  // 14 periods
  EXPECT_NE(error_of(datum + "gnss: {enabled: true, latency_s: 2.9}").find("gnss.latency_s"),
            std::string::npos);
}

TEST(SimSensors, EstimatedOdometryPublishesNoOdometryButTheSensorsAndTheTruth) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/otter.yaml";
  p.publish_odometry = false;
  p.sensors = file("sensors/usv.yaml");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  std::map<std::string, int> n;
  ex.observe([&](const std::string& ch, const std::uint8_t*, int, TimeUs) { ++n[ch]; });
  ex.run_until(2 * kUsPerSecond);
  EXPECT_EQ(n[channels::kOdometry], 0);
  EXPECT_GE(n[channels::kGroundTruth], 40);
  EXPECT_GE(n[channels::kImu], 199);
  EXPECT_GE(n[channels::kGnss], 9);
  EXPECT_GE(n[channels::kPower], 19);
  EXPECT_EQ(node.rejected(), 0);
  // At rest the battery draws the hotel load only: 15 W at 16.8 V.
  EXPECT_NEAR(node.sensors().battery().current(), 15.0 / 16.8, 0.01);
}

}  // namespace
}  // namespace tiller::sim
