// The Navigator's sensor drivers against their datasheets, through the fake buses:
// BMP280 (the datasheet's compensation example), ICM-20602 (set-up sequence, ids, conversions,
// self-test), AK09915 (ids, byte order, flags), ADS1115 (config word, codes, conversions), and
// tiller-power's ADS1115 node with the Power Sense Module's scaling.
#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>
#include <numbers>

#include <string>
#include <vector>
#include "i2c/fake_bus.hpp"

#include <tiller/heartbeat_t.hpp>
#include <tiller/power_t.hpp>

#include "core/config.hpp"
#include "runtime/channels.hpp"
#include "sensors/ads1115.hpp"
#include "sensors/ads1115_power_node.hpp"
#include "sensors/ak09915.hpp"
#include "sensors/bmp280.hpp"
#include "sensors/fake/navigator_models.hpp"
#include "sensors/icm20602.hpp"
#include "sensors/mmc5983.hpp"
#include "spi/fake_spi.hpp"

namespace {
using namespace tiller;
using namespace tiller::sensors;

TEST(Bmp280, DatasheetCompensationExample) {
  // BMP280 datasheet, section 8.2 (table 14): trimming values and raw readings -> 25.08 degC,
  // 100653.27 Pa; the integer code of 3.11.3 gives t_fine 128422.
  bmp280::Calibration c;
  c.t1 = 27504;
  c.t2 = 26435;
  c.t3 = -1000;
  c.p1 = 36477;
  c.p2 = -10685;
  c.p3 = 3024;
  c.p4 = 2855;
  c.p5 = 140;
  c.p6 = -7;
  c.p7 = 15500;
  c.p8 = -14600;
  c.p9 = 6000;
  const auto r = bmp280::compensate(c, 519888, 415148);
  EXPECT_EQ(r.t_fine, 128422);
  EXPECT_EQ(r.temperature_centi_c, 2508);
  EXPECT_NEAR(r.temperature_c, 25.08, 0.005);
  EXPECT_NEAR(r.pressure_pa, 100653.27, 0.02);  // the table rounds each step
  // The integer code's Q24.8 result: 25767233 / 256 = 100653.25 Pa (0.02 Pa below the doubles).
  EXPECT_NEAR(r.pressure_q24_8 / 256.0, 100653.25, 0.01);
  bmp280::Calibration broken = c;
  broken.p1 = 0;
  EXPECT_EQ(bmp280::compensate(broken, 519888, 415148).pressure_q24_8, 0u);
  EXPECT_EQ(bmp280::compensate(broken, 519888, 415148).pressure_pa, 0.0);
}

TEST(Bmp280, ThroughTheBusReadsTrimmingAndBurst) {
  i2c::FakeBus bus;
  fake::Bmp280Model chip;
  bus.attach(bmp280::kAddress, &chip);
  bmp280::Device dev(bus, bmp280::kAddress, bmp280::Config{});
  ASSERT_EQ(dev.start(), 0);
  EXPECT_EQ(dev.calibration().t1, 27504);
  EXPECT_EQ(dev.calibration().p8, -14600);
  EXPECT_EQ(chip.regs[bmp280::kRegCtrlMeas], (2 << 5) | (5 << 2) | 3);  // x2, x16, normal
  EXPECT_EQ(chip.regs[bmp280::kRegConfig], 4 << 2);                     // filter 16
  bmp280::Result r;
  ASSERT_EQ(dev.read(r), 0);
  EXPECT_EQ(r.temperature_centi_c, 2508);
  EXPECT_NEAR(r.pressure_pa, 100653.27, 0.02);
  chip.regs[bmp280::kRegId] = 0x60;  // a BME280
  EXPECT_EQ(dev.start(), EPROTO);
  EXPECT_EQ(dev.chip_id(), 0x60);
  bus.detach(bmp280::kAddress);
  EXPECT_EQ(dev.start(), ENXIO);
}

TEST(Icm20602, ConversionsFromTheSensitivityTables) {
  icm20602::Config c;  // +-1000 deg/s (32.8 LSB per deg/s), +-8 g (4096 LSB/g)
  icm20602::Burst b{};
  b[0] = 0x01;
  b[1] = 0x10;  // accel x = 0x1000 = 4096 -> 1 g
  b[3] = 0xF0;  // accel y = 0xF000 = -4096 -> -1 g
  b[7] = 0x0C;
  b[8] = 0xC4;  // temperature 0x0CC4 = 3268 -> 3268 / 326.8 + 25 = 35 degC
  b[9] = 0x01;
  b[10] = 0x48;  // gyro x 0x0148 = 328 -> 10 deg/s
  const auto s = icm20602::convert(b, c);
  EXPECT_TRUE(s.data_ready);
  EXPECT_DOUBLE_EQ(s.accel[0], 9.80665);
  EXPECT_DOUBLE_EQ(s.accel[1], -9.80665);
  EXPECT_DOUBLE_EQ(s.accel[2], 0.0);
  EXPECT_DOUBLE_EQ(s.temperature_c, 35.0);
  EXPECT_NEAR(s.gyro[0], 10.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(icm20602::gyro_lsb_per_dps(icm20602::GyroRange::dps250), 131.0);
  EXPECT_DOUBLE_EQ(icm20602::accel_lsb_per_g(icm20602::AccelRange::g16), 2048.0);
}

TEST(Icm20602, StartResetsChecksIdAndConfigures) {
  spi::FakeSpi bus("/dev/spidev1.0");
  fake::Icm20602Model chip;
  bus.attach(&chip);
  icm20602::Config c;
  c.gyro_range = icm20602::GyroRange::dps2000;
  c.accel_range = icm20602::AccelRange::g4;
  c.sample_rate_div = 4;
  icm20602::Device dev(bus, c);
  ASSERT_EQ(dev.start(), 0);
  EXPECT_EQ(chip.resets, 2);  // power-on and DEVICE_RESET
  EXPECT_EQ(chip.regs[icm20602::kRegGyroConfig], 3 << 3);
  EXPECT_EQ(chip.regs[icm20602::kRegAccelConfig], 1 << 3);
  EXPECT_EQ(chip.regs[icm20602::kRegSmplrtDiv], 4);
  EXPECT_EQ(chip.regs[icm20602::kRegI2cIf], icm20602::kI2cIfDis);
  EXPECT_EQ(chip.regs[icm20602::kRegPwrMgmt1], icm20602::kClkPll);  // awake
  EXPECT_EQ(chip.regs[icm20602::kRegIntEnable], icm20602::kDataRdyInt);
  // A sample: flat, package up, 1 g on +z; the data-ready flag clears on read.
  bus.set_time(bus.now() + 5000);
  icm20602::Burst b{};
  ASSERT_EQ(dev.read(b), 0);
  auto s = icm20602::convert(b, c);
  EXPECT_TRUE(s.data_ready);
  EXPECT_NEAR(s.accel[2], 9.80665, 9.80665 / 8192);
  EXPECT_NEAR(s.temperature_c, 30.0, 1.0 / 326.8);
  ASSERT_EQ(dev.read(b), 0);
  EXPECT_FALSE(icm20602::convert(b, c).data_ready);
  // Another chip, and nothing on the bus (MISO high: 0xFF).
  chip.regs[icm20602::kRegWhoAmI] = 0x70;
  icm20602::Device other(bus, c);
  bus.attach(nullptr);
  EXPECT_EQ(other.start(), ENODEV);
  bus.fail(EIO, 1);
  EXPECT_EQ(other.start(), EIO);
}

TEST(Icm20602, WrongWhoAmIIsNamed) {
  spi::FakeSpi bus;
  struct Mpu6500 : fake::Icm20602Model {
    void on_transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n, TimeUs t) override {
      fake::Icm20602Model::on_transfer(tx, rx, n, t);
      regs[icm20602::kRegWhoAmI] = 0x70;
    }
  } chip;
  bus.attach(&chip);
  icm20602::Device dev(bus, {});
  EXPECT_EQ(dev.start(), EPROTO);
  EXPECT_EQ(dev.who_am_i(), 0x70);
}

TEST(Icm20602, SelfTestAgainstTheFactoryTrim) {
  // Factory code 60 -> ST_OTP = 2620 * 1.01^59 = 4712.6 LSB; a response of 3000 LSB is 0.637
  // (passes: gyro >= 0.5, accel 0.5 .. 1.5); 1000 LSB is 0.212 (fails).
  EXPECT_NEAR(icm20602::factory_self_test(60), 2620.0 * std::pow(1.01, 59), 1e-9);
  EXPECT_NEAR(icm20602::factory_self_test(60), 4712.6, 0.1);
  spi::FakeSpi bus;
  fake::Icm20602Model chip;
  bus.attach(&chip);
  icm20602::Device dev(bus, {});
  icm20602::SelfTest st;
  ASSERT_EQ(dev.self_test(10, st), 0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(st.gyro_ratio[i], 3000 / 4712.6, 0.002);
    EXPECT_NEAR(st.accel_ratio[i], 3000 / 4712.6, 0.002);
  }
  EXPECT_TRUE(st.passed);
  EXPECT_EQ(chip.regs[icm20602::kRegGyroConfig], 2 << 3);  // configured again afterwards
  chip.self_test_lsb = 1000;
  ASSERT_EQ(dev.self_test(10, st), 0);
  EXPECT_FALSE(st.passed);
}

TEST(Ak09915, IdsModesAndLittleEndianMicroTesla) {
  EXPECT_EQ(ak09915::continuous_mode(100), 0x08);
  EXPECT_EQ(ak09915::continuous_mode(10), 0x02);
  EXPECT_EQ(ak09915::continuous_mode(200), 0x0C);
  EXPECT_EQ(ak09915::continuous_mode(30), -1);
  ak09915::Burst b{};
  b[0] = ak09915::kDrdy;
  b[1] = 0x00;
  b[2] = 0x01;  // HX = 0x0100 = 256 -> 38.4 uT
  b[3] = 0x9C;
  b[4] = 0xFF;  // HY = 0xFF9C = -100 -> -15 uT
  b[8] = ak09915::kHofl;
  const auto s = ak09915::convert(b);
  EXPECT_TRUE(s.data_ready);
  EXPECT_TRUE(s.overflow);
  EXPECT_NEAR(s.field_ut[0], 38.4, 1e-12);
  EXPECT_NEAR(s.field_ut[1], -15.0, 1e-12);

  i2c::FakeBus bus;
  fake::Ak09915Model chip;
  bus.attach(ak09915::kAddress, &chip);
  ak09915::Device dev(bus, ak09915::kAddress, 100);
  ASSERT_EQ(dev.start(), 0);
  EXPECT_EQ(chip.regs[ak09915::kRegCntl2], 0x08);
  bus.set_time(bus.now() + 10'000);
  ASSERT_EQ(dev.read(b), 0);
  const auto t = ak09915::convert(b);
  EXPECT_TRUE(t.data_ready);
  EXPECT_NEAR(t.field_ut[0], 20.0, 0.15);
  EXPECT_NEAR(t.field_ut[2], 40.0, 0.15);
  ASSERT_EQ(dev.read(b), 0);  // ST2 was read: no new data yet
  EXPECT_FALSE(ak09915::convert(b).data_ready);
  chip.wia2 = 0x09;  // an AK09916
  EXPECT_EQ(dev.start(), EPROTO);
}

TEST(Ads1115, ConfigWordCodesAndConversions) {
  // AIN0 single-ended, +-2.048 V, 128 SPS: the reset word 0x8583 with MUX 100 = 0xC583.
  EXPECT_EQ(ads1115::single_shot_word(0, 2, 4), 0xC583);
  EXPECT_EQ(ads1115::single_shot_word(3, 1, 7),
            0x8000 | (7 << 12) | (1 << 9) | 0x100 | (7 << 5) | 3);
  EXPECT_EQ(ads1115::pga_code(4.096), 1);
  EXPECT_EQ(ads1115::pga_code(3.3), -1);
  EXPECT_EQ(ads1115::data_rate_code(860), 7);
  EXPECT_EQ(ads1115::data_rate_code(100), -1);
  EXPECT_EQ(ads1115::conversion_us(4), 8594);  // 1.1 / 128 s
  // Table 8-1: 0x7FFF = +FS (2^15 - 1) / 2^15, 0x8000 = -FS, LSB = FS / 2^15.
  EXPECT_DOUBLE_EQ(ads1115::volts(0x7FFF, 2), 2.048 * 32767 / 32768);
  EXPECT_DOUBLE_EQ(ads1115::volts(0x8000, 2), -2.048);
  EXPECT_DOUBLE_EQ(ads1115::volts(0x0001, 2), 62.5e-6);

  i2c::FakeBus bus;
  fake::Ads1115Model chip;
  chip.input_v[2] = 1.0;
  bus.attach(ads1115::kAddress, &chip);
  ads1115::Device dev(bus, ads1115::kAddress, 1, 7);
  ASSERT_EQ(dev.probe(), 0);
  ASSERT_EQ(dev.start(2), 0);
  bus.set_time(bus.now() + ads1115::conversion_us(7));
  std::uint16_t raw = 0;
  ASSERT_EQ(dev.read(raw), 0);
  EXPECT_EQ(raw, 8000);  // 1.0 V / 4.096 V * 32768
  EXPECT_DOUBLE_EQ(ads1115::volts(raw, 1), 1.0);
}

// MMC5983MA: the 18-bit codes by hand. X 131072 + 16384 (+1 G = 100 uT): Xout0 0x90, Xout1 0x00;
// Y 131072 - 8192 (-50 uT): 0x78, 0x00; Z 131072 + 3: 0x80, 0x00 and XYZout2 bits 3:2 = 11;
// Status Meas_M_Done. The set-up: soft reset, product id 0x30, automatic SET/RESET, continuous
// 100 Hz with the periodic set; another id is EPROTO.
TEST(Mmc5983, CodesAndSetUp) {
  const mmc5983::Burst b = {0x90, 0x00, 0x78, 0x00, 0x80, 0x00, 0x0C, 0x00, 0x01};
  const auto s = mmc5983::convert(b);
  EXPECT_TRUE(s.data_ready);
  EXPECT_DOUBLE_EQ(s.field_ut[0], 100.0);
  EXPECT_DOUBLE_EQ(s.field_ut[1], -50.0);
  EXPECT_DOUBLE_EQ(s.field_ut[2], 3.0 / 16384.0 * 100.0);
  EXPECT_EQ(mmc5983::continuous_freq(100), 5);
  EXPECT_EQ(mmc5983::continuous_freq(200), -1);
  i2c::FakeBus bus;
  fake::Mmc5983Model chip;
  chip.field_ut[0] = 25.0;
  chip.field_ut[1] = -12.5;
  chip.field_ut[2] = 43.0;
  bus.attach(mmc5983::kAddress, &chip);
  mmc5983::Device dev(bus, mmc5983::kAddress, 100);
  ASSERT_EQ(dev.start(), 0);
  EXPECT_EQ(chip.regs[mmc5983::kRegControl0], 0x20);
  EXPECT_EQ(chip.regs[mmc5983::kRegControl2], 0x80 | 0x08 | 5);
  bus.set_time(bus.now() + 20'000);
  mmc5983::Burst r{};
  ASSERT_EQ(dev.read(r), 0);
  const auto m = mmc5983::convert(r);
  ASSERT_TRUE(m.data_ready);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.field_ut[i], chip.field_ut[i], 0.0031);  // 6.1 nT
  ASSERT_EQ(dev.read(r), 0);
  EXPECT_FALSE(mmc5983::convert(r).data_ready);  // read once: no new sample yet
  fake::Mmc5983Model other;
  other.product_id = 0x12;
  bus.attach(mmc5983::kAddress, &other);
  EXPECT_EQ(dev.start(), EPROTO);
  EXPECT_EQ(dev.product_id(), 0x12);
}

struct PowerBus : Bus {
  std::vector<power_t> got;
  heartbeat_t hb{};
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    if (channel.rfind("TILLER_HEARTBEAT", 0) == 0) {
      ASSERT_EQ(hb.decode(data, 0, size), size);
      return;
    }
    if (channel != channels::kPower) return;
    power_t m{};
    ASSERT_EQ(m.decode(data, 0, size), size);
    got.push_back(m);
  }
};

// The Navigator's ADS1115 with the Power Sense Module at 16.0 V and 10.0 A: AIN2 = 16 / 11 V,
// AIN3 = 0.330 + 10 / 37.8788 V. By hand at +-4.096 V (125 uV per code): AIN2 11636 codes ->
// 1.4545 V x 11 = 15.9995 V; AIN3 4752 codes -> (0.594 - 0.330) x 37.8788 = 10.000 A. Voltage and
// current alternate, one power_t every second tick; 1 s at 10 A is 2.78 mAh. The device gone: a
// FAULT naming it after fault_after ticks, nothing published; back: sampling again.
TEST(Ads1115PowerNode, PowerSenseModuleScalingAndAMissingDevice) {
  const auto p = load_ads1115_power_params(config::Value::parse(
      "device: ads1115\nvoltage_channel: 2\ncurrent_channel: 3\nrate_hz: 20\n", "p.yaml"));
  i2c::FakeBus bus{"/dev/i2c-1"};
  fake::Ads1115Model chip;
  chip.input_v[2] = 16.0 / 11.0;
  chip.input_v[3] = 0.330 + 10.0 / 37.8788;
  bus.attach(ads1115::kAddress, &chip);
  Ads1115PowerNode node(p, bus);
  PowerBus out;
  node.attach(&out);
  TimeUs t = 0;
  for (; t <= 1'050'000; t += 50'000) node.tick(t);
  ASSERT_TRUE(node.device_ready());
  ASSERT_EQ(out.got.size(), 10u);  // at 0.10, 0.20, ..., 1.00 s
  EXPECT_EQ(out.got[0].utime, 100'000);
  EXPECT_NEAR(out.got[0].voltage, 15.9995, 1e-4);
  EXPECT_NEAR(out.got[0].current, 10.000, 0.005);
  EXPECT_NEAR(out.got[0].power, 15.9995 * out.got[0].current, 1e-9);
  EXPECT_EQ(out.got[0].monitor, "ads1115@/dev/i2c-1:0x48");
  EXPECT_NEAR(out.got.back().consumed_charge, 10.0 * 0.9 / 3600, 1e-5);  // 0.1 .. 1.0 s
  EXPECT_EQ(node.counter_value("samples"), 10);
  EXPECT_EQ(node.counter_value("conversion.not_ready"), 0);
  bus.detach(ads1115::kAddress);
  const std::size_t before = out.got.size();
  for (; t <= 2'600'000; t += 50'000) node.tick(t);
  EXPECT_FALSE(node.device_ready());
  EXPECT_EQ(out.got.size(), before);
  EXPECT_EQ(out.hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(out.hb.status.find("ads1115 on /dev/i2c-1 at 0x48"), std::string::npos)
      << out.hb.status;
  bus.attach(ads1115::kAddress, &chip);
  for (; t <= 5'000'000; t += 50'000) node.tick(t);
  EXPECT_TRUE(node.device_ready());
  EXPECT_GT(out.got.size(), before);
  EXPECT_EQ(out.hb.state, heartbeat_t::STATE_OK) << out.hb.status;
}

TEST(Ads1115PowerNode, ConfigErrorsNameTheKey) {
  const auto err = [](const std::string& text) {
    try {
      load_ads1115_power_params(config::Value::parse(text, "p.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(err("voltage_channel: 2\ncurrent_channel: 2\n").find("current_channel"),
            std::string::npos);
  EXPECT_NE(err("full_scale_v: 3.3\n").find("full_scale_v"), std::string::npos);
  EXPECT_NE(err("data_rate_sps: 100\n").find("data_rate_sps"), std::string::npos);
  EXPECT_NE(err("data_rate_sps: 8\nrate_hz: 20\n").find("rate_hz"), std::string::npos);
  EXPECT_NE(err("shunt_ohm: 0.1\n").find("shunt_ohm"), std::string::npos);  // an INA226 key
  EXPECT_EQ(err("device: ads1115\n"), "accepted");
}

}  // namespace
