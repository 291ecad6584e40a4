#include "sensors/ms5837.hpp"

#include <cerrno>

namespace tiller::sensors::ms5837 {

std::uint8_t crc4(const Prom& prom) {
  std::uint16_t n[8];
  for (int i = 0; i < 7; ++i) n[i] = prom[static_cast<std::size_t>(i)];
  n[0] &= 0x0FFF;  // the CRC nibble is replaced by 0
  n[7] = 0;        // subsidiary value
  std::uint16_t rem = 0;
  for (int cnt = 0; cnt < 16; ++cnt) {
    rem ^= (cnt % 2 == 1) ? (n[cnt >> 1] & 0x00FF) : (n[cnt >> 1] >> 8);
    for (int bit = 8; bit > 0; --bit)
      rem = (rem & 0x8000) ? static_cast<std::uint16_t>((rem << 1) ^ 0x3000)
                           : static_cast<std::uint16_t>(rem << 1);
  }
  return static_cast<std::uint8_t>((rem >> 12) & 0x0F);
}

Osr osr_for(int ratio) {
  // Maximum conversion times from the MS5837-30BA datasheet (ADC conversion time, max).
  static constexpr Osr kTable[] = {{256, 0x00, 600},   {512, 0x02, 1170},  {1024, 0x04, 2280},
                                   {2048, 0x06, 4540}, {4096, 0x08, 9040}, {8192, 0x0A, 18080}};
  for (const Osr& o : kTable)
    if (o.ratio == ratio) return o;
  return Osr{};
}

Result compensate(Model model, const Prom& c, std::uint32_t d1, std::uint32_t d2) {
  const bool b30 = model == Model::ba30;
  Result r;
  r.dT = static_cast<std::int32_t>(d2) - (static_cast<std::int32_t>(c[5]) << 8);
  const std::int64_t dt = r.dT;
  r.temp = static_cast<std::int32_t>(2000 + ((dt * c[6]) >> 23));
  if (b30) {
    r.off = (static_cast<std::int64_t>(c[2]) << 16) + ((c[4] * dt) >> 7);
    r.sens = (static_cast<std::int64_t>(c[1]) << 15) + ((c[3] * dt) >> 8);
  } else {
    r.off = (static_cast<std::int64_t>(c[2]) << 17) + ((c[4] * dt) >> 6);
    r.sens = (static_cast<std::int64_t>(c[1]) << 16) + ((c[3] * dt) >> 7);
  }
  const int p_shift = b30 ? 13 : 15;
  r.p = static_cast<std::int32_t>(((d1 * r.sens >> 21) - r.off) >> p_shift);

  // Second order temperature compensation.
  const std::int64_t t = r.temp, t20 = (t - 2000) * (t - 2000);
  std::int64_t ti = 0, offi = 0, sensi = 0;
  if (b30) {
    if (t < 2000) {
      ti = (3 * dt * dt) >> 33;
      offi = (3 * t20) >> 1;
      sensi = (5 * t20) >> 3;
      if (t < -1500) {
        const std::int64_t t15 = (t + 1500) * (t + 1500);
        offi += 7 * t15;
        sensi += 4 * t15;
      }
    } else {
      ti = (2 * dt * dt) >> 37;
      offi = t20 >> 4;
      sensi = 0;
    }
  } else if (t < 2000) {
    ti = (11 * dt * dt) >> 35;
    offi = (31 * t20) >> 3;
    sensi = (63 * t20) >> 5;
  }
  const std::int64_t off2 = r.off - offi, sens2 = r.sens - sensi;
  r.temp2 = static_cast<std::int32_t>(t - ti);
  r.p2 = static_cast<std::int32_t>(((d1 * sens2 >> 21) - off2) >> p_shift);
  r.temperature_c = r.temp2 / 100.0;
  r.pressure_pa = b30 ? r.p2 * 10.0 : r.p2 * 1.0;  // 0.1 mbar = 10 Pa; 0.01 mbar = 1 Pa
  return r;
}

int Device::start() {
  if (int e = bus_.write(address_, &kCmdReset, 1)) return e;
  bus_.wait_us(kResetUs);
  for (std::size_t k = 0; k < prom_.size(); ++k) {
    const std::uint8_t cmd = static_cast<std::uint8_t>(kCmdPromRead + 2 * k);
    std::uint8_t b[2] = {0, 0};
    if (int e = bus_.write_read(address_, &cmd, 1, b, 2)) return e;
    prom_[k] = static_cast<std::uint16_t>((b[0] << 8) | b[1]);
  }
  return prom_valid(prom_) ? 0 : EBADMSG;
}

int Device::start_conversion(bool pressure) {
  const std::uint8_t cmd =
      static_cast<std::uint8_t>((pressure ? kCmdConvertD1 : kCmdConvertD2) | osr_.code);
  return bus_.write(address_, &cmd, 1);
}

int Device::read_adc(std::uint32_t& value) {
  std::uint8_t b[3] = {0, 0, 0};
  if (int e = bus_.write_read(address_, &kCmdAdcRead, 1, b, 3)) return e;
  value = (std::uint32_t{b[0]} << 16) | (std::uint32_t{b[1]} << 8) | b[2];
  return value == 0 ? EAGAIN : 0;
}

}  // namespace tiller::sensors::ms5837
