#include "sensors/fake/navigator_models.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sensors/ads1115.hpp"
#include "sensors/ak09915.hpp"
#include "sensors/bmp280.hpp"
#include "sensors/icm20602.hpp"
#include "sensors/mmc5983.hpp"

namespace tiller::sensors::fake {

namespace {
std::int16_t clamp16(double v) {
  return static_cast<std::int16_t>(std::clamp(std::lround(v), -32768L, 32767L));
}
void put_be(std::uint8_t* p, std::int16_t v) {
  p[0] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  p[1] = static_cast<std::uint8_t>(v & 0xFF);
}
}  // namespace

// ICM-20602 -----------------------------------------------------------------------------------

void Icm20602Model::reset() {
  regs.fill(0);
  regs[icm20602::kRegWhoAmI] = icm20602::kWhoAmI;
  regs[icm20602::kRegPwrMgmt1] = 0x41;  // SLEEP, CLKSEL 1
  regs[icm20602::kRegSelfTestXAccel] = regs[0x0E] = regs[0x0F] = 60;
  regs[icm20602::kRegSelfTestXGyro] = regs[0x51] = regs[0x52] = 60;
  ++resets;
}

void Icm20602Model::latch() {
  using namespace icm20602;
  const auto gr = static_cast<GyroRange>((regs[kRegGyroConfig] >> 3) & 3);
  const auto ar = static_cast<AccelRange>((regs[kRegAccelConfig] >> 3) & 3);
  const bool gst = (regs[kRegGyroConfig] & kSelfTestXyz) != 0;
  const bool ast = (regs[kRegAccelConfig] & kSelfTestXyz) != 0;
  for (int i = 0; i < 3; ++i) {
    const double a = accel[i] / kG * accel_lsb_per_g(ar) + (ast ? self_test_lsb : 0);
    const double g =
        gyro[i] * 180.0 / std::numbers::pi * gyro_lsb_per_dps(gr) + (gst ? self_test_lsb : 0);
    put_be(&regs[kRegAccelXoutH + 2 * i], clamp16(a));
    put_be(&regs[0x43 + 2 * i], clamp16(g));
  }
  put_be(&regs[0x41], clamp16((temperature_c - kTempOffsetC) * kTempSensitivity));
  regs[kRegIntStatus] |= kDataRdyInt;
  ++samples;
}

void Icm20602Model::advance(TimeUs now) {
  if ((regs[icm20602::kRegPwrMgmt1] & 0x40) != 0) return;  // asleep
  const TimeUs period = 1000 * (1 + regs[icm20602::kRegSmplrtDiv]);
  if (now < next_sample_) return;
  latch();
  next_sample_ = now + period;
}

void Icm20602Model::on_transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n,
                                TimeUs now) {
  (void)now;
  if (n == 0) return;
  const std::uint8_t reg = tx[0] & 0x7F;
  if (tx[0] & spi::kReadBit) {
    if (rx) {
      rx[0] = 0;
      for (std::size_t i = 1; i < n; ++i) rx[i] = regs[(reg + i - 1) & 0x7F];
    }
    if (reg == icm20602::kRegIntStatus) regs[icm20602::kRegIntStatus] &= ~icm20602::kDataRdyInt;
    return;
  }
  for (std::size_t i = 1; i < n; ++i) {
    const std::uint8_t r = (reg + i - 1) & 0x7F;
    if (r == icm20602::kRegWhoAmI) continue;  // read only
    if (r == icm20602::kRegPwrMgmt1 && (tx[i] & icm20602::kDeviceReset)) {
      reset();
      return;
    }
    regs[r] = tx[i];
  }
}

// AK09915 -------------------------------------------------------------------------------------

void Ak09915Model::reset() {
  regs.fill(0);
  regs[0x00] = ak09915::kWia1;
  regs[0x01] = wia2;
}

void Ak09915Model::advance(TimeUs now) {
  const std::uint8_t mode = regs[ak09915::kRegCntl2];
  int hz = 0;
  for (int r : {10, 20, 50, 100, 200})
    if (ak09915::continuous_mode(r) == mode) hz = r;
  if (hz == 0 || now < next_sample_) return;
  next_sample_ = now + 1'000'000 / hz;
  if (regs[0x10] & ak09915::kDrdy) regs[0x10] |= ak09915::kDor;
  regs[0x10] |= ak09915::kDrdy;
  for (int i = 0; i < 3; ++i) {
    const std::int16_t v = clamp16(field_ut[i] / ak09915::kMicroTeslaPerLsb);
    regs[0x11 + 2 * i] = static_cast<std::uint8_t>(v & 0xFF);
    regs[0x12 + 2 * i] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  }
  regs[0x18] = overflow ? ak09915::kHofl : 0;
}

int Ak09915Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  (void)now;
  if (n == 0) return 0;
  ptr_ = d[0];
  for (std::size_t i = 1; i < n; ++i) {
    const std::uint8_t r = static_cast<std::uint8_t>(ptr_ + i - 1);
    if (r == ak09915::kRegCntl3 && (d[i] & ak09915::kSoftReset)) {
      reset();
      continue;
    }
    if (r < regs.size()) regs[r] = d[i];
  }
  return 0;
}

int Ak09915Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  (void)now;
  bool st2 = false;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = ptr_ + i;
    out[i] = r < regs.size() ? regs[r] : 0;
    st2 = st2 || r == 0x18;
  }
  if (st2) regs[0x10] = 0;  // reading ST2 ends the read: DRDY and DOR clear
  return 0;
}

// BMP280 --------------------------------------------------------------------------------------

Bmp280Model::Bmp280Model() {
  regs[bmp280::kRegId] = bmp280::kChipId;
  // The datasheet's example trimming values (section 8.2): T1..T3, P1..P9, little-endian.
  const std::int32_t words[12] = {27504, 26435, -1000, 36477, -10685, 3024,
                                  2855,  140,   -7,    15500, -14600, 6000};
  for (int i = 0; i < 12; ++i) {
    const auto u = static_cast<std::uint16_t>(words[i]);
    regs[bmp280::kRegCalib + 2 * i] = static_cast<std::uint8_t>(u & 0xFF);
    regs[bmp280::kRegCalib + 2 * i + 1] = static_cast<std::uint8_t>(u >> 8);
  }
  set_adc(519888, 415148);
}

void Bmp280Model::set_adc(std::int32_t adc_t, std::int32_t adc_p) {
  regs[0xF7] = static_cast<std::uint8_t>(adc_p >> 12);
  regs[0xF8] = static_cast<std::uint8_t>((adc_p >> 4) & 0xFF);
  regs[0xF9] = static_cast<std::uint8_t>((adc_p & 0x0F) << 4);
  regs[0xFA] = static_cast<std::uint8_t>(adc_t >> 12);
  regs[0xFB] = static_cast<std::uint8_t>((adc_t >> 4) & 0xFF);
  regs[0xFC] = static_cast<std::uint8_t>((adc_t & 0x0F) << 4);
}

int Bmp280Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  (void)now;
  if (n == 0) return 0;
  ptr_ = d[0];
  if (n >= 2 && ptr_ != bmp280::kRegReset && ptr_ != bmp280::kRegId) regs[ptr_] = d[1];
  return 0;
}

int Bmp280Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  (void)now;
  for (std::size_t i = 0; i < n; ++i) out[i] = regs[(ptr_ + i) & 0xFF];
  return 0;
}

// ADS1115 -------------------------------------------------------------------------------------

int Ads1115Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  if (n == 0) return 0;
  ptr_ = d[0] & 0x03;
  if (n >= 3 && ptr_ == ads1115::kRegConfig) {
    config = static_cast<std::uint16_t>((d[1] << 8) | d[2]);
    if (config & ads1115::kOs) {
      busy_ = true;
      ready_at_ = now + 1'000'000 / ads1115::data_rate_sps((config >> 5) & 7);
      config &= static_cast<std::uint16_t>(~ads1115::kOs);
    }
  }
  return 0;
}

void Ads1115Model::advance(TimeUs now) {
  if (!busy_ || now < ready_at_) return;
  busy_ = false;
  config |= ads1115::kOs;
  const int mux = (config >> 12) & 7;
  const double v = mux >= 4 ? input_v[mux - 4] : 0.0;
  const double fs = ads1115::full_scale_v((config >> 9) & 7);
  conversion = static_cast<std::uint16_t>(clamp16(std::floor(v / fs * 32768.0)));
  ++conversions;
}

int Ads1115Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  advance(now);
  const std::uint16_t v = ptr_ == ads1115::kRegConfig ? config : conversion;
  if (n >= 1) out[0] = static_cast<std::uint8_t>(v >> 8);
  if (n >= 2) out[1] = static_cast<std::uint8_t>(v & 0xFF);
  return 0;
}

int Mmc5983Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  if (n == 0) return 0;
  ptr_ = d[0] & 0x3F;
  if (n >= 2) {
    regs[ptr_] = d[1];
    if (ptr_ == mmc5983::kRegControl1 && (d[1] & mmc5983::kSoftReset)) {
      regs.fill(0);
      next_sample_ = now;
    }
  }
  return 0;
}

void Mmc5983Model::advance(TimeUs now) {
  const std::uint8_t c2 = regs[mmc5983::kRegControl2];
  if (!(c2 & mmc5983::kContinuous)) return;
  static constexpr int kHz[8] = {0, 1, 10, 20, 50, 100, 200, 1000};
  const int hz = kHz[c2 & 7];
  if (hz == 0 || now < next_sample_) return;
  next_sample_ = now + 1'000'000 / hz;
  for (int i = 0; i < 3; ++i) {
    double code = std::round(field_ut[i] / 100.0 * mmc5983::kCountsPerGauss + mmc5983::kNull);
    code = std::clamp(code, 0.0, 262143.0);
    const auto c = static_cast<std::uint32_t>(code);
    regs[2 * i] = static_cast<std::uint8_t>(c >> 10);
    regs[2 * i + 1] = static_cast<std::uint8_t>(c >> 2);
    regs[6] = static_cast<std::uint8_t>((regs[6] & ~(0x03u << (6 - 2 * i))) |
                                        ((c & 0x03u) << (6 - 2 * i)));
  }
  regs[mmc5983::kRegStatus] |= mmc5983::kMeasDone;
  ++samples;
}

int Mmc5983Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  advance(now);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t r = static_cast<std::uint8_t>((ptr_ + i) & 0x3F);
    out[i] = r == mmc5983::kRegProductId ? product_id : regs[r];
  }
  if (ptr_ <= mmc5983::kRegStatus && ptr_ + n > mmc5983::kRegStatus)
    regs[mmc5983::kRegStatus] &= static_cast<std::uint8_t>(~mmc5983::kMeasDone);  // read: done
  return 0;
}

}  // namespace tiller::sensors::fake
