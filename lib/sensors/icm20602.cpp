#include "sensors/icm20602.hpp"

#include <cerrno>
#include <cmath>
#include <numbers>

namespace tiller::sensors::icm20602 {

double gyro_lsb_per_dps(GyroRange r) {
  static constexpr double k[4] = {131.0, 65.5, 32.8, 16.4};
  return k[static_cast<int>(r) & 3];
}

double accel_lsb_per_g(AccelRange r) {
  static constexpr double k[4] = {16384.0, 8192.0, 4096.0, 2048.0};
  return k[static_cast<int>(r) & 3];
}

std::array<std::array<std::uint8_t, 2>, 8> setup_writes(const Config& c) {
  return {{{kRegPwrMgmt1, kClkPll},
           {kRegI2cIf, kI2cIfDis},
           {kRegPwrMgmt2, 0x00},  // all axes on
           {kRegConfig, static_cast<std::uint8_t>(c.dlpf_cfg & 0x07)},
           {kRegSmplrtDiv, c.sample_rate_div},
           {kRegGyroConfig, static_cast<std::uint8_t>(static_cast<int>(c.gyro_range) << 3)},
           {kRegAccelConfig, static_cast<std::uint8_t>(static_cast<int>(c.accel_range) << 3)},
           {kRegAccelConfig2, static_cast<std::uint8_t>(c.accel_dlpf_cfg & 0x07)}}};
}

Sample convert(const Burst& b, const Config& c) {
  Sample s;
  s.data_ready = (b[0] & kDataRdyInt) != 0;
  const double a_scale = kG / accel_lsb_per_g(c.accel_range);
  const double g_scale = (std::numbers::pi / 180.0) / gyro_lsb_per_dps(c.gyro_range);
  for (int i = 0; i < 3; ++i) {
    s.accel[i] = be16(&b[1 + 2 * i]) * a_scale;
    s.gyro[i] = be16(&b[9 + 2 * i]) * g_scale;
  }
  s.temperature_c = be16(&b[7]) / kTempSensitivity + kTempOffsetC;
  return s;
}

double factory_self_test(std::uint8_t code) {
  return code == 0 ? 0.0 : 2620.0 * std::pow(1.01, code - 1.0);
}

int Device::start() {
  if (int e = bus_.write_reg(kRegPwrMgmt1, kDeviceReset)) return e;
  bus_.wait_us(kResetUs);
  if (int e = bus_.read_regs(kRegWhoAmI, &who_am_i_, 1)) return e;
  if (who_am_i_ == 0x00 || who_am_i_ == 0xFF) return ENODEV;
  if (who_am_i_ != kWhoAmI) return EPROTO;
  for (const auto& w : setup_writes(c_)) {
    if (int e = bus_.write_reg(w[0], w[1])) return e;
  }
  return bus_.write_reg(kRegIntEnable, kDataRdyInt);
}

int Device::average(int samples, double accel[3], double gyro[3]) {
  for (int i = 0; i < 3; ++i) accel[i] = gyro[i] = 0;
  const std::int64_t period_us = 1000 * (1 + c_.sample_rate_div);
  Burst b{};
  for (int k = 0; k < samples; ++k) {
    bus_.wait_us(period_us);
    if (int e = read(b)) return e;
    for (int i = 0; i < 3; ++i) {
      accel[i] += be16(&b[1 + 2 * i]);
      gyro[i] += be16(&b[9 + 2 * i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    accel[i] /= samples;
    gyro[i] /= samples;
  }
  return 0;
}

int Device::self_test(int samples, SelfTest& out) {
  const Config saved = c_;
  c_.gyro_range = GyroRange::dps250;  // the factory values are at FS 0
  c_.accel_range = AccelRange::g2;
  int err = start();
  double a0[3], g0[3], a1[3], g1[3];
  if (err == 0) err = average(samples, a0, g0);
  if (err == 0) err = bus_.write_reg(kRegGyroConfig, kSelfTestXyz);
  if (err == 0) err = bus_.write_reg(kRegAccelConfig, kSelfTestXyz);
  bus_.wait_us(20'000);  // the outputs settle (datasheet: 20 ms)
  if (err == 0) err = average(samples, a1, g1);
  std::uint8_t ta[3] = {0, 0, 0}, tg[3] = {0, 0, 0};
  if (err == 0) err = bus_.read_regs(kRegSelfTestXAccel, ta, 3);
  if (err == 0) err = bus_.read_regs(kRegSelfTestXGyro, tg, 3);
  c_ = saved;
  if (err != 0) return err;
  out.passed = true;
  for (int i = 0; i < 3; ++i) {
    const double fa = factory_self_test(ta[i]), fg = factory_self_test(tg[i]);
    out.accel_ratio[i] = fa > 0 ? (a1[i] - a0[i]) / fa : 0;
    out.gyro_ratio[i] = fg > 0 ? (g1[i] - g0[i]) / fg : 0;
    out.passed = out.passed && out.gyro_ratio[i] >= 0.5 && out.accel_ratio[i] >= 0.5 &&
                 out.accel_ratio[i] <= 1.5;
  }
  return start();
}

}  // namespace tiller::sensors::icm20602
