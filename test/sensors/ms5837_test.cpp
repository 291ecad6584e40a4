// MS5837 (sensors/ms5837.hpp, sensors/pressure_node.hpp): the datasheets' worked examples, the
// PROM CRC-4, and tiller-pressure's node on the fake bus (samples, missing device, bus errors,
// bad CRC, strict config).
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <vector>

#include <tiller/pressure_t.hpp>

#include "core/config.hpp"
#include "i2c/fake_bus.hpp"
#include "runtime/node.hpp"
#include "sensors/fake/ms5837_model.hpp"
#include "sensors/ms5837.hpp"
#include "sensors/pressure_node.hpp"

namespace tiller::sensors {
namespace {

using ms5837::Model;
using ms5837::Prom;

// MS5837-30BA datasheet, "pressure and temperature calculation", example / typical column.
constexpr Prom kProm30 = {0x2000, 34982, 36352, 20328, 22354, 26646, 26146};  // CRC nibble 2
constexpr std::uint32_t kD1_30 = 4958179, kD2_30 = 6815414;
// MS5837-02BA datasheet, same table.
constexpr Prom kProm02 = {0x0000, 46372, 43981, 29059, 27842, 31553, 28165};
constexpr std::uint32_t kD1_02 = 6465444, kD2_02 = 8077636;

TEST(Ms5837, Datasheet30BaWorkedExample) {
  const auto r = ms5837::compensate(Model::ba30, kProm30, kD1_30, kD2_30);
  EXPECT_EQ(r.dT, -5962);
  EXPECT_EQ(r.temp, 1981);  // 19.81 degC
  // The datasheet prints OFF = 2381326464; C2 * 2^16 + C4 * dT / 2^7 with its own C2, C4 and dT
  // is 2381323464 (a misprint of one digit; P = 39998 follows from either).
  EXPECT_EQ(r.off, 2381323464);
  EXPECT_EQ(r.sens, 1145816755);
  EXPECT_EQ(r.p, 39998);  // 3999.8 mbar
  // Second order (TEMP < 20 degC): Ti = 3 dT^2 / 2^33 = 0, OFFi = 3 (TEMP-2000)^2 / 2 = 541,
  // SENSi = 5 (TEMP-2000)^2 / 2^3 = 225 -> P2 = 39998 (the correction is below one LSB here).
  EXPECT_EQ(r.temp2, 1981);
  EXPECT_EQ(r.p2, 39998);
  EXPECT_DOUBLE_EQ(r.pressure_pa, 399980.0);
  EXPECT_DOUBLE_EQ(r.temperature_c, 19.81);
}

TEST(Ms5837, Datasheet02BaWorkedExample) {
  const auto r = ms5837::compensate(Model::ba02, kProm02, kD1_02, kD2_02);
  EXPECT_EQ(r.dT, 68);
  EXPECT_EQ(r.temp, 2000);
  EXPECT_EQ(r.off, 5764707214);
  EXPECT_EQ(r.sens, 3039050829);
  EXPECT_EQ(r.p, 110002);   // 1100.02 mbar
  EXPECT_EQ(r.p2, 110002);  // TEMP = 20.00 degC: no second order correction
  EXPECT_DOUBLE_EQ(r.pressure_pa, 110002.0);
}

TEST(Ms5837, SecondOrderCorrectsColdAndWarmWater) {
  // 30BA, D2 lowered below 20 degC, then raised above it: the corrections
  // follow the datasheet's branches (hand-computed with its formulas).
  const auto cold = ms5837::compensate(Model::ba30, kProm30, kD1_30, 6'000'000);
  EXPECT_LT(cold.temp, 2000);
  const std::int64_t dt = cold.dT, t20 = (cold.temp - 2000LL) * (cold.temp - 2000LL);
  EXPECT_EQ(cold.temp2, cold.temp - ((3 * dt * dt) >> 33));
  const std::int64_t off2 = cold.off - ((3 * t20) >> 1), sens2 = cold.sens - ((5 * t20) >> 3);
  EXPECT_EQ(cold.p2, ((kD1_30 * sens2 >> 21) - off2) >> 13);
  EXPECT_NE(cold.p2, cold.p);
  const auto hot = ms5837::compensate(Model::ba30, kProm30, kD1_30, 7'300'000);
  EXPECT_GT(hot.temp, 2000);
  const std::int64_t hdt = hot.dT, h20 = (hot.temp - 2000LL) * (hot.temp - 2000LL);
  EXPECT_EQ(hot.temp2, hot.temp - ((2 * hdt * hdt) >> 37));
  EXPECT_EQ(hot.p2, ((kD1_30 * hot.sens >> 21) - (hot.off - (h20 >> 4))) >> 13);
}

TEST(Ms5837, Crc4) {
  // The datasheet's CRC-4 over its example coefficients with word 0 = 0x0000: remainder 2
  // (worked by hand with the datasheet's code: 16 bytes, polynomial 0x3000).
  Prom p = kProm30;
  p[0] = 0x0000;
  EXPECT_EQ(ms5837::crc4(p), 2);
  EXPECT_TRUE(ms5837::prom_valid(kProm30));
  // The CRC nibble itself does not enter the calculation.
  p[0] = 0xF000;
  EXPECT_EQ(ms5837::crc4(p), 2);
  // Any single flipped bit in C1..C6 or word 0's low 12 bits is detected.
  for (std::size_t w = 0; w < 7; ++w) {
    for (int b = 0; b < (w == 0 ? 12 : 16); ++b) {
      Prom q = kProm30;
      q[w] = static_cast<std::uint16_t>(q[w] ^ (1u << b));
      EXPECT_FALSE(ms5837::prom_valid(q)) << "word " << w << " bit " << b;
    }
  }
}

TEST(Ms5837, OsrTable) {
  EXPECT_EQ(ms5837::osr_for(256).code, 0x00);
  EXPECT_EQ(ms5837::osr_for(8192).code, 0x0A);
  EXPECT_EQ(ms5837::osr_for(8192).max_conversion_us, 18080);
  EXPECT_EQ(ms5837::osr_for(300).ratio, 0);
}

// Collects what a node publishes.
struct Capture : Bus {
  std::vector<pressure_t> samples;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    if (ch != "TILLER_PRESSURE") return;
    pressure_t m;
    if (m.decode(d, 0, n) == n) samples.push_back(m);
  }
};

struct Rig {
  i2c::FakeBus bus{"/dev/i2c-1"};
  fake::Ms5837Model dev{kProm30};
  PressureParams p;
  Capture out;
  Rig() {
    dev.d1 = kD1_30;
    dev.d2 = kD2_30;
    p.rate_hz = 20;  // ticks at 40 Hz (25 ms > 9.04 ms at OSR 4096)
    p.water_density = 1025;
  }
  void run(PressureNode& n, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += n.tick_period()) n.tick(t);
  }
};

TEST(PressureNode, PublishesTheDatasheetPressureAndItsDepth) {
  Rig r;
  r.bus.attach(0x76, &r.dev);
  PressureNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);  // 41 ticks: set-up, then D2/D1 pairs
  ASSERT_EQ(r.out.samples.size(), 20u);
  const auto& s = r.out.samples.back();
  EXPECT_DOUBLE_EQ(s.pressure, 399980.0);
  EXPECT_DOUBLE_EQ(s.temperature, 19.81);
  EXPECT_NEAR(s.depth, (399980.0 - 101325.0) / (1025 * 9.80665), 1e-12);  // 29.712 m
  EXPECT_EQ(s.sensor, "ms5837-30ba@/dev/i2c-1:0x76");
  EXPECT_EQ(r.dev.early_reads, 0);
  EXPECT_EQ(r.dev.resets, 1);
  EXPECT_EQ(n.counter_value("samples"), 20);
  EXPECT_EQ(n.counter_value("bus.errors"), 0);
  EXPECT_TRUE(n.device_ready());
}

TEST(PressureNode, MissingDeviceIsFaultNamingBusAndAddressAndIsRetried) {
  Rig r;  // nothing attached at 0x76
  PressureNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 2 * kUsPerSecond + 1);
  EXPECT_TRUE(r.out.samples.empty());
  EXPECT_FALSE(n.device_ready());
  EXPECT_EQ(n.counter_value("init.failures"), 3);  // t = 0, 1 s, 2 s (retry_period 1 s)
  EXPECT_EQ(n.counter_value("bus.retries"), 3);
  // Plugged in later: found at the next retry (t = 3 s), then 20 samples in the next second.
  r.bus.attach(0x76, &r.dev);
  r.run(n, 2 * kUsPerSecond + 25'000, 4 * kUsPerSecond);
  EXPECT_TRUE(n.device_ready());
  EXPECT_EQ(n.counter_value("init.failures"), 3);
  EXPECT_EQ(r.out.samples.size(), 20u);
}

TEST(PressureNode, HeartbeatSaysFaultWithBusAndAddress) {
  Rig r;
  PressureNode n(r.p, r.bus);
  struct Hb : Bus {
    heartbeat_t last;
    void publish(std::string_view ch, const std::uint8_t* d, int sz) override {
      if (ch == "TILLER_HEARTBEAT_PRESSURE") last.decode(d, 0, sz);
    }
  } hb;
  n.attach(&hb);
  n.tick(0);
  EXPECT_EQ(hb.last.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(hb.last.status.find("ms5837-30ba on /dev/i2c-1 at 0x76"), std::string::npos)
      << hb.last.status;
  EXPECT_NE(hb.last.status.find("ENXIO"), std::string::npos) << hb.last.status;
}

TEST(PressureNode, BusErrorsAreRetriedCountedAndLeadToFaultAfterFive) {
  Rig r;
  r.bus.attach(0x76, &r.dev);
  PressureNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  const auto before = r.out.samples.size();
  // One failed transaction: the retry succeeds, nothing lost.
  r.bus.fail(0x76, EREMOTEIO, 1);
  r.run(n, 525'000, 1'000'000);
  EXPECT_EQ(n.counter_value("bus.retries"), 1);
  EXPECT_EQ(n.counter_value("bus.errors"), 0);
  EXPECT_GT(r.out.samples.size(), before);
  // The bus fails for good: 5 failed ticks in a row -> lost, FAULT, re-set-up every second.
  r.bus.fail(0x76, EREMOTEIO, -1);
  r.run(n, 1'025'000, 1'500'000);
  EXPECT_FALSE(n.device_ready());
  EXPECT_EQ(n.counter_value("bus.errors"), 5);
  r.bus.clear_fault(0x76);
  const auto lost_at = r.out.samples.size();
  r.run(n, 1'525'000, 3'000'000);
  EXPECT_TRUE(n.device_ready());
  EXPECT_GT(r.out.samples.size(), lost_at);
}

TEST(PressureNode, BadPromCrcIsRefused) {
  Rig r;
  Prom bad = kProm30;
  bad[3] ^= 0x0100;
  fake::Ms5837Model dev(bad);
  dev.d1 = kD1_30;
  dev.d2 = kD2_30;
  r.bus.attach(0x76, &dev);
  PressureNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 1'500'000);
  EXPECT_TRUE(r.out.samples.empty());
  EXPECT_EQ(n.counter_value("prom.crc_errors"), 2);
}

TEST(PressureConfig, StrictLoader) {
  const auto p = load_pressure_file(TILLER_SOURCE_DIR "/config/sensors/pressure_bar30.yaml");
  EXPECT_EQ(p.bus, "/dev/i2c-1");
  EXPECT_EQ(p.address, 0x76);
  EXPECT_EQ(p.osr.ratio, 4096);
  EXPECT_EQ(p.water_density, 997);
  auto error = [](const std::string& text) {
    try {
      load_pressure_params(config::Value::parse(text, "p.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(error("osr: 300\n").find("p.yaml:1: osr"), std::string::npos) << error("osr: 300\n");
  EXPECT_NE(error("osr: 300\n").find("one of 256"), std::string::npos);
  EXPECT_NE(error("osr: 8192\nrate_hz: 40\n").find("rate_hz"), std::string::npos);
  EXPECT_NE(error("water: salty\n").find("water"), std::string::npos);
  EXPECT_NE(error("water: custom\n").find("water_density"), std::string::npos);
  EXPECT_NE(error("adress: 0x76\n").find("unknown key"), std::string::npos);
  EXPECT_NE(error("address: 0x40\n").find("address"), std::string::npos);
  EXPECT_EQ(load_pressure_params(config::Value::parse("water: salt\n")).water_density, 1025);
}

}  // namespace
}  // namespace tiller::sensors
