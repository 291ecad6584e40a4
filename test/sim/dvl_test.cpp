// The simulated DVL (lib/sim/sensor_models.hpp DvlModel, scheduled by SensorSuite, loaded from
// the `dvl:` section of config/sim/sensors/*.yaml): noise statistics against hand-computed
// bounds, fom and covariance, the altitude above a flat seabed, bottom lock lost outside the
// altitude range with the fields dvl_t's contract asks for, the 8 Hz rate on a 10 ms step,
// --dvl-outage windows that publish nothing, determinism by seed (and the other sensors' noise
// unchanged by adding it), the config's errors, and tiller-sim publishing TILLER_DVL.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/sensor_suite.hpp"
#include "sim/sim_node.hpp"
#include "sim/sim_options.hpp"

namespace tiller::sim {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

TrueState moving(double depth) {
  TrueState s;
  s.eta << 3, -4, depth, 0.05, -0.02, 1.0;
  s.nu << 0.5, -0.2, 0.1, 0.01, 0.02, 0.03;  // body FRD over ground
  return s;
}

SensorParams file(const std::string& name) {
  return load_sensor_file(kSrc + "/config/sim/" + name, 10'000);
}

TEST(DvlModel, NoiseHasTheConfiguredSigmaAndBiasAndTheFomSaysSo) {
  DvlModelParams p;  // 0.005 m/s white per axis, seabed 20 m
  p.bias_m_s = {0.01, -0.02, 0.0};
  DvlModel m(p, 5);
  const TrueState s = moving(5.0);
  const int n = 20'000;
  double sum[3] = {}, sum2[3] = {};
  dvl_t o{};
  for (int k = 0; k < n; ++k) {
    m.sample(TimeUs{k} * 125'000, s, o);
    ASSERT_EQ(checks::check(o), nullptr);
    ASSERT_TRUE(o.bottom_lock);
    for (int i = 0; i < 3; ++i) {
      const double e = o.velocity[i] - s.nu[i];
      sum[i] += e;
      sum2[i] += e * e;
    }
  }
  // By hand: the mean of n draws of N(b, s^2) is within 4 s / sqrt(n) = 4 * 0.005 / 141.4 =
  // 1.41e-4 m/s of b; the sample standard deviation within s (1 +- 4 / sqrt(2 n)) = s (1 +- 0.02)
  // (both 4-sigma bounds: a false failure about once in 16 000 runs, and the seed is fixed).
  for (int i = 0; i < 3; ++i) {
    const double mean = sum[i] / n;
    const double sd = std::sqrt(sum2[i] / n - mean * mean);
    EXPECT_NEAR(mean, p.bias_m_s[static_cast<std::size_t>(i)], 1.41e-4) << "axis " << i;
    EXPECT_NEAR(sd, 0.005, 0.005 * 0.02) << "axis " << i;
  }
  EXPECT_EQ(o.fom, 0.005);
  EXPECT_DOUBLE_EQ(o.velocity_covariance[0], 2.5e-5);
  EXPECT_DOUBLE_EQ(o.velocity_covariance[4], 2.5e-5);
  EXPECT_DOUBLE_EQ(o.velocity_covariance[8], 2.5e-5);
  for (int i : {1, 2, 3, 5, 6, 7}) EXPECT_EQ(o.velocity_covariance[i], 0.0);
  EXPECT_EQ(o.beams_valid, 4);
  EXPECT_EQ(o.status, 0);
  EXPECT_EQ(o.sensor, "sim");
  EXPECT_EQ(o.utime, TimeUs{n - 1} * 125'000);
}

TEST(DvlModel, AltitudeIsTheSeabedLessTheDepthAndTheLockIsLostOutsideItsRange) {
  DvlModelParams p;
  p.velocity_std_m_s = 0;  // exact numbers
  p.seabed_depth_m = 60;
  DvlModel m(p, 1);
  dvl_t o{};
  const TrueState s = moving(12.5);
  m.sample(1000, s, o);
  EXPECT_TRUE(o.bottom_lock);
  EXPECT_DOUBLE_EQ(o.altitude, 47.5);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(o.velocity[i], s.nu[i]);  // over ground, body FRD
  EXPECT_EQ(checks::check(o), nullptr);
  m.sample(2000, moving(10.0), o);  // exactly max_altitude_m (50 m): still locked
  EXPECT_TRUE(o.bottom_lock);
  EXPECT_DOUBLE_EQ(o.altitude, 50.0);
  auto expect_unlocked = [&](double depth) {
    m.sample(3000, moving(depth), o);
    EXPECT_FALSE(o.bottom_lock) << depth;
    for (int i = 0; i < 3; ++i) EXPECT_EQ(o.velocity[i], 0.0);
    for (int i = 0; i < 9; ++i) EXPECT_EQ(o.velocity_covariance[i], 0.0);
    EXPECT_EQ(o.altitude, -1.0);
    EXPECT_EQ(o.beams_valid, 0);
    EXPECT_EQ(o.fom, DvlModelParams::kNoLockFom);
    EXPECT_EQ(checks::check(o), nullptr) << checks::check(o);
  };
  expect_unlocked(9.9);    // 50.1 m above the bottom: beyond the A50's 50 m
  expect_unlocked(0.0);    // at the surface, 60 m
  expect_unlocked(59.97);  // 3 cm: below the 5 cm minimum
  expect_unlocked(61.0);   // below the seabed (a vehicle cannot be; no lock, not a negative one)
  m.sample(4000, moving(59.9), o);  // 10 cm: locked again
  EXPECT_TRUE(o.bottom_lock);
  EXPECT_NEAR(o.altitude, 0.1, 1e-12);
}

struct DvlLog {
  std::vector<dvl_t> dvl;
  std::map<std::string, std::string> bytes;  // per channel, every message encoded
};

DvlLog run(const SensorParams& p, std::uint64_t seed, double seconds, double depth = 5.0) {
  SensorSuite suite(p, seed);
  DvlLog log;
  TrueState s = moving(depth);
  double th[4] = {5, 5, 5, 5};
  s.thrust = th;
  s.n_thrusters = 4;
  for (TimeUs t = 10'000; t <= from_seconds(seconds); t += 10'000) {
    s.eta[0] = 0.5 * to_seconds(t);
    suite.step(t, 0.01, s);
    suite.release(t, [&](const char* ch, const auto& m) {
      EXPECT_EQ(checks::check(m), nullptr) << ch;
      std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
      m.encode(b.data(), 0, static_cast<int>(b.size()));
      log.bytes[ch].append(b.begin(), b.end());
      if constexpr (std::is_same_v<std::decay_t<decltype(m)>, dvl_t>) {
        EXPECT_EQ(std::string(ch), channels::kDvl);
        log.dvl.push_back(m);
      }
    });
  }
  return log;
}

TEST(DvlSuite, TheRovFileSamplesAt8HzOnA10MsStep) {
  const SensorParams p = file("sensors/rov.yaml");
  ASSERT_TRUE(p.dvl_timing.enabled);
  EXPECT_EQ(p.dvl_timing.period_us, 125'000);
  EXPECT_EQ(p.dvl.seabed_depth_m, 20.0);
  EXPECT_EQ(p.dvl.max_altitude_m, 50.0);
  const DvlLog log = run(p, 3, 100.0);
  // 8 Hz over 100 s: the multiples of 125 ms from 0.125 s to 100 s, each sampled at the first
  // 10 ms step at or after it.
  ASSERT_EQ(log.dvl.size(), 800u);
  for (std::size_t k = 0; k < log.dvl.size(); ++k) {
    const TimeUs grid = static_cast<TimeUs>(k + 1) * 125'000;
    EXPECT_EQ(log.dvl[k].utime, (grid + 9'999) / 10'000 * 10'000) << k;
    EXPECT_TRUE(log.dvl[k].bottom_lock);
    EXPECT_DOUBLE_EQ(log.dvl[k].altitude, 15.0);  // 20 m seabed, 5 m deep
  }
  // A 10 Hz DVL on the same step: a whole number of steps, exactly 100 ms apart.
  SensorParams q = p;
  q.dvl_timing.period_us = 100'000;
  EXPECT_EQ(run(q, 3, 10.0).dvl.size(), 100u);
}

TEST(DvlSuite, OutageWindowsFromTheOptionPublishNothingAndShiftNoNoise) {
  SimParams sp;
  sp.sensors = file("sensors/rov.yaml");
  const SensorParams plain = sp.sensors;
  apply(sim_overrides(std::vector<std::string>{"--dvl-outage", "20:10,50:5"}), sp);
  ASSERT_EQ(sp.sensors.dvl_outages.size(), 2u);
  const DvlLog a = run(sp.sensors, 9, 100.0);
  const DvlLog b = run(plain, 9, 100.0);
  // 800 samples less 10 s and 5 s of 8 Hz: 800 - 80 - 40.
  EXPECT_EQ(a.dvl.size(), 680u);
  for (const auto& m : a.dvl) {
    EXPECT_FALSE(m.utime >= 20'000'000 && m.utime < 30'000'000) << m.utime;
    EXPECT_FALSE(m.utime >= 50'000'000 && m.utime < 55'000'000) << m.utime;
  }
  // Outside the windows the messages are those of the run without outages, bit for bit.
  std::size_t j = 0;
  for (const auto& m : b.dvl) {
    const bool out = (m.utime >= 20'000'000 && m.utime < 30'000'000) ||
                     (m.utime >= 50'000'000 && m.utime < 55'000'000);
    if (out) continue;
    ASSERT_LT(j, a.dvl.size());
    EXPECT_EQ(a.dvl[j].utime, m.utime);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(a.dvl[j].velocity[i], m.velocity[i]);
    ++j;
  }
  EXPECT_EQ(j, a.dvl.size());
  // The option is checked like --gnss-outage, and needs a DVL.
  try {
    (void)sim_overrides(std::vector<std::string>{"--dvl-outage", "20:-1"});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(),
                 "--dvl-outage: expected START_S:DURATION_S (start >= 0, duration > 0, s; a comma "
                 "list for several, e.g. 40:20,90:5), got '20:-1'");
  }
  SimParams usv;
  usv.sensors = file("sensors/usv.yaml");
  EXPECT_FALSE(usv.sensors.dvl_timing.enabled);  // a surface boat has no DVL
  try {
    apply(sim_overrides(std::vector<std::string>{"--dvl-outage", "5:5"}), usv);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("--dvl-outage: expected the sensors file"),
              std::string::npos)
        << e.what();
  }
  SimParams none;
  EXPECT_THROW(apply(sim_overrides(std::vector<std::string>{"--dvl-outage", "5:5"}), none),
               std::runtime_error);
}

TEST(DvlSuite, SameSeedSameBytesAndTheOtherSensorsKeepTheirNoise) {
  const SensorParams p = file("sensors/rov.yaml");
  const DvlLog a = run(p, 21, 30.0);
  const DvlLog b = run(p, 21, 30.0);
  const DvlLog c = run(p, 22, 30.0);
  EXPECT_EQ(a.bytes.at(channels::kDvl), b.bytes.at(channels::kDvl));
  EXPECT_NE(a.bytes.at(channels::kDvl), c.bytes.at(channels::kDvl));
  // Without the DVL every other sensor's messages are the same bytes: its own generator.
  SensorParams off = p;
  off.dvl_timing.enabled = false;
  const DvlLog d = run(off, 21, 30.0);
  EXPECT_EQ(d.bytes.count(channels::kDvl), 0u);
  for (const char* ch :
       {channels::kImu, channels::kHeading, channels::kPressure, channels::kPower, channels::kLeak})
    EXPECT_EQ(a.bytes.at(ch), d.bytes.at(ch)) << ch;
  // Lost lock at 60 m of water and 5 m depth (55 m): published, unlocked, valid by contract.
  SensorParams deep = p;
  deep.dvl.seabed_depth_m = 60;
  const DvlLog e = run(deep, 21, 2.0);
  ASSERT_EQ(e.dvl.size(), 16u);
  for (const auto& m : e.dvl) EXPECT_FALSE(m.bottom_lock);
}

TEST(DvlConfig, ErrorsNameTheFileTheKeyAndTheExpectation) {
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
  const std::string e1 = error_of("dvl: {enabled: true}");
  EXPECT_NE(e1.find("s.yaml"), std::string::npos) << e1;
  EXPECT_NE(e1.find("dvl.seabed_depth_m"), std::string::npos) << e1;
  const std::string e2 = error_of("dvl: {enabled: true, seabed_depth_m: 20, rate_hz: 40}");
  EXPECT_NE(e2.find("dvl.rate_hz: expected a number in [1, 30]"), std::string::npos) << e2;
  const std::string e3 =
      error_of("dvl: {enabled: true, seabed_depth_m: 20, min_altitude_m: 5, max_altitude_m: 2}");
  EXPECT_NE(e3.find("dvl.max_altitude_m: expected min_altitude_m < max_altitude_m"),
            std::string::npos)
      << e3;
  const std::string e4 = error_of("dvl: {enabled: true, seabed_depth_m: 20, bias_m_s: [0, 1]}");
  EXPECT_NE(e4.find("dvl.bias_m_s"), std::string::npos) << e4;
  const std::string e5 = error_of("dvl: {enabled: false, velocity_sd_m_s: 0.01}");
  EXPECT_NE(e5.find("dvl.velocity_sd_m_s: unknown key"), std::string::npos) << e5;
  const std::string e6 = error_of("dvl: {enabled: true, seabed_depth_m: 20, velocity_std_m_s: -1}");
  EXPECT_NE(e6.find("dvl.velocity_std_m_s"), std::string::npos) << e6;
  const std::string e7 = error_of("dvl: {enabled: true, seabed_depth_m: 20, outages: 5}");
  EXPECT_NE(e7.find("dvl.outages: expected a list of {start_s, duration_s}"), std::string::npos)
      << e7;
  EXPECT_EQ(error_of("dvl: {enabled: true, seabed_depth_m: 20, rate_hz: 15, outages: "
                     "[{start_s: 1, duration_s: 2}]}"),
            "no error");
}

TEST(DvlSim, TillerSimPublishesTheDvlOnTillerDvlForTheBlueRov2) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/bluerov2.yaml";
  p.sensors = file("sensors/rov.yaml");
  p.initial_eta[2] = 8.0;
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  std::vector<dvl_t> got;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch != channels::kDvl) return;
    dvl_t m{};
    ASSERT_GE(m.decode(d, 0, n), 0);
    got.push_back(m);
  });
  ex.run_until(from_seconds(10));
  ASSERT_EQ(got.size(), 80u);
  const auto& last = got.back();
  EXPECT_EQ(checks::check(last), nullptr);
  EXPECT_TRUE(last.bottom_lock);
  // The last sample is of the state at 10 s, the model's now: slightly buoyant, it has risen,
  // and the altitude is the 20 m seabed less that depth.
  EXPECT_EQ(last.utime, from_seconds(10));
  EXPECT_LT(node.model().eta()[2], 8.0);
  EXPECT_DOUBLE_EQ(last.altitude, 20.0 - node.model().eta()[2]);
}

}  // namespace
}  // namespace tiller::sim
