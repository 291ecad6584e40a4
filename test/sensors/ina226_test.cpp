// INA226 (sensors/ina226.hpp, sensors/power_node.hpp): the data sheet's configure / measure /
// calculate example (SBOS547 table 1), the calibration equation, the charge integrator with time
// passed in, and tiller-power's node on the fake bus (ids, reset detection, missing device, bus
// errors, strict config).
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <vector>

#include <tiller/heartbeat_t.hpp>
#include <tiller/power_t.hpp>

#include "core/config.hpp"
#include "i2c/fake_bus.hpp"
#include "runtime/node.hpp"
#include "sensors/fake/ina226_model.hpp"
#include "sensors/ina226.hpp"
#include "sensors/power_node.hpp"

namespace tiller::sensors {
namespace {

// Data sheet table 1, conditions: load 10 A, VCM 12 V, R_shunt 2 mOhm, Current_LSB 1 mA.
constexpr std::uint16_t kShunt = 0x1F40;    // 8000 x 2.5 uV = 20 mV
constexpr std::uint16_t kBus = 0x2570;      // 9584 x 1.25 mV = 11.98 V
constexpr std::uint16_t kCal = 0x0A00;      // 2560
constexpr std::uint16_t kCurrent = 0x2710;  // 10000 x 1 mA = 10 A
constexpr std::uint16_t kPower = 0x12B8;    // 4792 x 25 mW = 119.8 W

TEST(Ina226, DataSheetExample) {
  EXPECT_EQ(ina226::calibration(0.001, 0.002), kCal);  // 0.00512 / (1e-3 * 2e-3)
  EXPECT_DOUBLE_EQ(ina226::shunt_voltage(kShunt), 0.020);
  EXPECT_DOUBLE_EQ(ina226::bus_voltage(kBus), 11.98);
  EXPECT_DOUBLE_EQ(ina226::current(kCurrent, 0.001), 10.0);
  EXPECT_DOUBLE_EQ(ina226::power(kPower, 0.001), 119.8);
  // The chip's arithmetic (equations 3 and 4) in the fake gives the example's registers.
  fake::Ina226Model dev;
  dev.shunt = kShunt;
  dev.bus = kBus;
  const std::uint8_t cal[3] = {ina226::kRegCalibration, 0x0A, 0x00};
  dev.on_write(cal, 3, 0);
  EXPECT_EQ(dev.reg(ina226::kRegCurrent), kCurrent);
  EXPECT_EQ(dev.reg(ina226::kRegPower), kPower);
  // Step 1 of the example: the power-on configuration 0x4127 is AVG 1, 1.1 ms, 1.1 ms, MODE 7.
  EXPECT_EQ(ina226::config_word(0, 4, 4), ina226::kConfigPowerOn);
}

TEST(Ina226, CalibrationLimitsAndCodes) {
  // Data sheet equation 2: Current_LSB = 15 A / 2^15 = 457.8 uA with 2 mOhm -> CAL 5592.
  EXPECT_EQ(ina226::calibration(15.0 / 32768, 0.002), 5592);
  EXPECT_EQ(ina226::calibration(1e-6, 0.002), 0);  // 2,560,000: beyond 15 bits
  EXPECT_EQ(ina226::calibration(0.001, 0), 0);
  EXPECT_EQ(ina226::averaging_code(16), 2);
  EXPECT_EQ(ina226::averaging_code(17), -1);
  EXPECT_EQ(ina226::conversion_time_code(8244), 7);
  EXPECT_EQ(ina226::conversion_time_code(1000), -1);
  EXPECT_EQ(ina226::config_word(2, 4, 4), 0x4527);
  EXPECT_EQ(ina226::sample_period_us(16, 1100, 1100), 35200);
  // A negative current (charging) in two's complement.
  EXPECT_DOUBLE_EQ(ina226::current(static_cast<std::uint16_t>(-2500), 0.001), -2.5);
}

TEST(Ina226, IntegratorChargeAndEnergy) {
  // 10 A and 119.8 W for 360 s in 0.1 s steps: 1 Ah, 11.98 Wh.
  ina226::Integrator in(kUsPerSecond);
  for (TimeUs t = 0; t <= 360 * kUsPerSecond; t += 100'000) in.add(t, 10.0, 119.8);
  EXPECT_NEAR(in.charge_ah(), 1.0, 1e-12);
  EXPECT_NEAR(in.energy_wh(), 11.98, 1e-12);
  // Trapezoid: a ramp 0 -> 2 A over 1 h is 1 Ah.
  ina226::Integrator ramp(kUsPerSecond);
  for (int k = 0; k <= 3600; ++k) ramp.add(k * kUsPerSecond, 2.0 * k / 3600, 0);
  EXPECT_NEAR(ramp.charge_ah(), 1.0, 1e-12);
  // A gap longer than max_gap is not integrated and is counted; a shorter one is.
  ina226::Integrator gap(kUsPerSecond);
  gap.add(0, 3600, 0);
  gap.add(2 * kUsPerSecond, 3600, 0);  // 2 s > 1 s
  EXPECT_EQ(gap.gaps(), 1);
  EXPECT_DOUBLE_EQ(gap.charge_ah(), 0);
  gap.add(3 * kUsPerSecond, 3600, 0);  // 1 s at 3600 A = 1 Ah
  EXPECT_NEAR(gap.charge_ah(), 1.0, 1e-12);
}

struct Capture : Bus {
  std::vector<power_t> samples;
  heartbeat_t hb;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    if (ch == "TILLER_POWER") {
      power_t m;
      if (m.decode(d, 0, n) == n) samples.push_back(m);
    } else if (ch == "TILLER_HEARTBEAT_POWER") {
      hb.decode(d, 0, n);
    }
  }
};

struct Rig {
  i2c::FakeBus bus{"/dev/i2c-1"};
  fake::Ina226Model dev;
  PowerParams p;
  Capture out;
  Rig() {
    dev.shunt = kShunt;
    dev.bus = kBus;
    p = load_power_params(config::Value::parse(
        "shunt_ohm: 0.002\nmax_current_a: 30\ncurrent_lsb_a: 0.001\nrate_hz: 10\n"));
  }
  void run(PowerNode& n, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += n.tick_period()) n.tick(t);
  }
};

TEST(PowerNode, PublishesTheDataSheetExampleAndIntegrates) {
  Rig r;
  r.bus.attach(0x40, &r.dev);
  PowerNode n(r.p, r.bus);
  n.attach(&r.out);
  EXPECT_EQ(r.p.calibration, kCal);
  EXPECT_EQ(r.p.config, 0x4527);               // AVG 16, 1.1 ms, 1.1 ms, continuous
  r.run(n, 0, 3600 * kUsPerSecond + 100'000);  // set-up at 0, samples from 0.1 s
  EXPECT_EQ(r.dev.resets(), 1);                // the reset at set-up
  EXPECT_EQ(r.dev.reg(ina226::kRegCalibration), kCal);
  ASSERT_EQ(r.out.samples.size(), 36001u);  // 0.1 s .. 3600.1 s
  const power_t& s = r.out.samples.back();
  EXPECT_DOUBLE_EQ(s.voltage, 11.98);
  EXPECT_DOUBLE_EQ(s.current, 10.0);
  EXPECT_DOUBLE_EQ(s.power, 119.8);
  // 10 A from 0.1 s to 3600.1 s: 10 Ah, 119.8 Wh.
  EXPECT_NEAR(s.consumed_charge, 10.0, 1e-9);
  EXPECT_NEAR(s.consumed_energy, 119.8, 1e-9);
  EXPECT_EQ(s.monitor, "ina226@/dev/i2c-1:0x40");
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_OK);
  EXPECT_EQ(n.counter_value("charge.gaps"), 0);
}

TEST(PowerNode, InvertedShuntAndCharging) {
  Rig r;
  r.p.invert_current = true;
  r.dev.shunt = static_cast<std::uint16_t>(-8000);  // -20 mV: 10 A the other way
  r.bus.attach(0x40, &r.dev);
  PowerNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  ASSERT_FALSE(r.out.samples.empty());
  EXPECT_DOUBLE_EQ(r.out.samples.back().current, 10.0);  // discharge after inversion
  EXPECT_DOUBLE_EQ(r.out.samples.back().power, 119.8);
  r.dev.shunt = 8000;  // now charging at 10 A
  r.run(n, kUsPerSecond + 100'000, 2 * kUsPerSecond);
  EXPECT_DOUBLE_EQ(r.out.samples.back().current, -10.0);
  EXPECT_DOUBLE_EQ(r.out.samples.back().power, -119.8);  // the unsigned register, signed
}

TEST(PowerNode, MissingDeviceWrongChipAndResetAreHandled) {
  Rig r;
  {
    PowerNode n(r.p, r.bus);  // nothing at 0x40
    n.attach(&r.out);
    r.run(n, 0, 2 * kUsPerSecond);
    EXPECT_EQ(n.counter_value("init.failures"), 3);
    EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
    EXPECT_NE(r.out.hb.status.find("ina226 on /dev/i2c-1 at 0x40: no answer"), std::string::npos)
        << r.out.hb.status;
    EXPECT_NE(r.out.hb.status.find("ENXIO"), std::string::npos);
  }
  {
    fake::Ina226Model other;  // an INA219 has no id registers; say a chip answering 0x0000
    other.manufacturer_id = 0;
    r.bus.attach(0x40, &other);
    PowerNode n(r.p, r.bus);
    n.attach(&r.out);
    r.run(n, 0, kUsPerSecond);
    EXPECT_NE(r.out.hb.status.find("not an INA226"), std::string::npos) << r.out.hb.status;
  }
  r.out.samples.clear();
  r.bus.attach(0x40, &r.dev);
  PowerNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, kUsPerSecond);
  const auto before = r.out.samples.size();
  r.dev.power_cycle();  // CAL back to 0: the current register would read 0 A
  r.run(n, kUsPerSecond + 100'000, 2 * kUsPerSecond);
  EXPECT_EQ(n.counter_value("device.resets"), 1);
  EXPECT_EQ(r.dev.reg(ina226::kRegCalibration), kCal);
  for (std::size_t i = before; i < r.out.samples.size(); ++i)
    EXPECT_DOUBLE_EQ(r.out.samples[i].current, 10.0);  // no 0 A sample was published
  // 1.1 s notices, 1.2 s sets up, samples from 1.3 s (the first conversion, 35.2 ms, is ready).
  EXPECT_EQ(r.out.samples.size(), before + 8u);
}

TEST(PowerNode, BusErrorsAreRetriedCountedAndLeadToFaultAfterFive) {
  Rig r;
  r.bus.attach(0x40, &r.dev);
  PowerNode n(r.p, r.bus);
  n.attach(&r.out);
  r.run(n, 0, 500'000);
  r.bus.fail(0x40, EIO, 1);
  r.run(n, 600'000, 700'000);
  EXPECT_EQ(n.counter_value("bus.retries"), 1);
  EXPECT_EQ(n.counter_value("bus.errors"), 0);
  r.bus.fail(0x40, EIO, -1);
  r.run(n, 800'000, 2 * kUsPerSecond);  // lost at 1.2 s (the fifth), next try at 2.2 s
  EXPECT_EQ(n.counter_value("bus.errors"), 5);
  EXPECT_FALSE(n.device_ready());
  EXPECT_EQ(r.out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(r.out.hb.status.find("5 reads failed in a row: EIO"), std::string::npos)
      << r.out.hb.status;
  r.bus.clear_fault(0x40);
  r.run(n, 2'100'000, 3 * kUsPerSecond);
  EXPECT_TRUE(n.device_ready());
}

TEST(PowerConfig, StrictLoader) {
  const auto p = load_power_file(TILLER_SOURCE_DIR "/config/sensors/power_ina226.yaml");
  EXPECT_EQ(p.address, 0x41);  // not the PCA9685's 0x40 on the same bus
  EXPECT_EQ(p.calibration, kCal);
  auto error = [](const std::string& text) {
    try {
      load_power_params(config::Value::parse(text, "power.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string base = "shunt_ohm: 0.002\nmax_current_a: 30\n";
  EXPECT_NE(error("max_current_a: 30\n").find("shunt_ohm: missing required key"),
            std::string::npos);
  EXPECT_NE(error(base + "current_lsb_a: 0.0001\n").find("power.yaml:3: current_lsb_a"),
            std::string::npos)
      << error(base + "current_lsb_a: 0.0001\n");
  EXPECT_NE(error("shunt_ohm: 0.00001\nmax_current_a: 0.01\n").find("CAL = 0.00512"),
            std::string::npos)
      << error("shunt_ohm: 0.00001\nmax_current_a: 0.01\n");
  EXPECT_NE(error(base + "averaging: 10\n").find("one of 1, 4, 16"), std::string::npos);
  EXPECT_NE(error(base + "bus_conversion_us: 1000\n").find("bus_conversion_us"), std::string::npos);
  EXPECT_NE(error(base + "averaging: 1024\nrate_hz: 10\n").find("rate_hz: expected at most"),
            std::string::npos)
      << error(base + "averaging: 1024\nrate_hz: 10\n");
  EXPECT_NE(error(base + "address: 0x50\n").find("address"), std::string::npos);
  EXPECT_NE(error(base + "shunt: 1\n").find("unknown key"), std::string::npos);
}

}  // namespace
}  // namespace tiller::sensors
