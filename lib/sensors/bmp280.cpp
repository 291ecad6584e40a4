#include "sensors/bmp280.hpp"

#include <cerrno>

namespace tiller::sensors::bmp280 {

namespace {
std::uint16_t u16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::int16_t s16(const std::uint8_t* p) {
  return static_cast<std::int16_t>(u16(p));
}
}  // namespace

Calibration decode_calibration(const std::array<std::uint8_t, 24>& b) {
  Calibration c;
  c.t1 = u16(&b[0]);
  c.t2 = s16(&b[2]);
  c.t3 = s16(&b[4]);
  c.p1 = u16(&b[6]);
  std::int16_t* p[8] = {&c.p2, &c.p3, &c.p4, &c.p5, &c.p6, &c.p7, &c.p8, &c.p9};
  for (int i = 0; i < 8; ++i) *p[i] = s16(&b[8 + 2 * i]);
  return c;
}

void decode_adc(const std::array<std::uint8_t, 6>& b, std::int32_t& adc_p, std::int32_t& adc_t) {
  adc_p = (b[0] << 12) | (b[1] << 4) | (b[2] >> 4);
  adc_t = (b[3] << 12) | (b[4] << 4) | (b[5] >> 4);
}

Result compensate(const Calibration& c, std::int32_t adc_t, std::int32_t adc_p) {
  Result r;
  // Temperature (datasheet 3.11.3, bmp280_compensate_T_int32).
  const std::int32_t t1 = c.t1, t2 = c.t2, t3 = c.t3;
  const std::int32_t v1 = (((adc_t >> 3) - (t1 << 1)) * t2) >> 11;
  const std::int32_t d = (adc_t >> 4) - t1;
  const std::int32_t v2 = (((d * d) >> 12) * t3) >> 14;
  r.t_fine = v1 + v2;
  r.temperature_centi_c = (r.t_fine * 5 + 128) >> 8;
  // Double precision (datasheet 8.1, bmp280_compensate_T_double / _P_double).
  {
    const double x = adc_t / 16384.0 - c.t1 / 1024.0, y = adc_t / 131072.0 - c.t1 / 8192.0;
    const double tf = x * c.t2 + y * y * c.t3;
    r.temperature_c = tf / 5120.0;
    double d1 = static_cast<std::int32_t>(tf) / 2.0 - 64000.0;
    double d2 = d1 * d1 * c.p6 / 32768.0;
    d2 = d2 + d1 * c.p5 * 2.0;
    d2 = d2 / 4.0 + c.p4 * 65536.0;
    d1 = (c.p3 * d1 * d1 / 524288.0 + c.p2 * d1) / 524288.0;
    d1 = (1.0 + d1 / 32768.0) * c.p1;
    if (d1 != 0.0) {
      double p = 1048576.0 - adc_p;
      p = (p - d2 / 4096.0) * 6250.0 / d1;
      d1 = c.p9 * p * p / 2147483648.0;
      d2 = p * c.p8 / 32768.0;
      r.pressure_pa = p + (d1 + d2 + c.p7) / 16.0;
    }
  }
  // Pressure (bmp280_compensate_P_int64).
  std::int64_t var1 = static_cast<std::int64_t>(r.t_fine) - 128000;
  std::int64_t var2 = var1 * var1 * c.p6;
  var2 = var2 + ((var1 * c.p5) * (std::int64_t{1} << 17));
  var2 = var2 + (static_cast<std::int64_t>(c.p4) * (std::int64_t{1} << 35));
  var1 = ((var1 * var1 * c.p3) >> 8) + ((var1 * c.p2) * (std::int64_t{1} << 12));
  var1 = (((std::int64_t{1} << 47) + var1) * c.p1) >> 33;
  if (var1 == 0) return r;  // dig_P1 = 0: no pressure (avoids a division by zero)
  std::int64_t p = 1048576 - adc_p;
  p = (((p * (std::int64_t{1} << 31)) - var2) * 3125) / var1;
  var1 = (static_cast<std::int64_t>(c.p9) * (p >> 13) * (p >> 13)) >> 25;
  var2 = (static_cast<std::int64_t>(c.p8) * p) >> 19;
  p = ((p + var1 + var2) >> 8) + (static_cast<std::int64_t>(c.p7) << 4);
  r.pressure_q24_8 = static_cast<std::uint32_t>(p);
  return r;
}

int Device::start() {
  if (int e = write(kRegReset, kResetValue)) return e;
  bus_.wait_us(kStartUs);
  if (int e = bus_.write_read(address_, &kRegId, 1, &id_, 1)) return e;
  if (id_ != kChipId) return EPROTO;
  std::array<std::uint8_t, 24> b{};
  if (int e = bus_.write_read(address_, &kRegCalib, 1, b.data(), b.size())) return e;
  cal_ = decode_calibration(b);
  if (cal_.p1 == 0) return EBADMSG;
  if (int e = write(kRegConfig, static_cast<std::uint8_t>((c_.t_sb << 5) | (c_.filter << 2))))
    return e;
  return write(kRegCtrlMeas, static_cast<std::uint8_t>((c_.osrs_t << 5) | (c_.osrs_p << 2) | 3));
}

int Device::read(Result& r) {
  std::array<std::uint8_t, 6> b{};
  if (int e = bus_.write_read(address_, &kRegPressMsb, 1, b.data(), b.size())) return e;
  std::int32_t adc_p = 0, adc_t = 0;
  decode_adc(b, adc_p, adc_t);
  r = compensate(cal_, adc_t, adc_p);
  return 0;
}

}  // namespace tiller::sensors::bmp280
