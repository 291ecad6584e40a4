#include "sensors/ads1115.hpp"

#include <cerrno>
#include <cmath>

namespace tiller::sensors::ads1115 {

namespace {
constexpr double kFsr[8] = {6.144, 4.096, 2.048, 1.024, 0.512, 0.256, 0.256, 0.256};
constexpr int kSps[8] = {8, 16, 32, 64, 128, 250, 475, 860};
}  // namespace

double full_scale_v(int pga) {
  return kFsr[pga & 7];
}

int pga_code(double fs) {
  for (int i = 0; i < 6; ++i)
    if (std::abs(kFsr[i] - fs) < 1e-9) return i;
  return -1;
}

int data_rate_code(int sps) {
  for (int i = 0; i < 8; ++i)
    if (kSps[i] == sps) return i;
  return -1;
}

int data_rate_sps(int code) {
  return kSps[code & 7];
}

std::uint16_t single_shot_word(int channel, int pga, int dr) {
  return static_cast<std::uint16_t>(kOs | ((4 + (channel & 3)) << 12) | ((pga & 7) << 9) | 0x0100 |
                                    ((dr & 7) << 5) | 0x0003);
}

std::int64_t conversion_us(int dr) {
  return static_cast<std::int64_t>(std::ceil(1.1e6 / kSps[dr & 7]));
}

int Device::probe() {
  std::uint8_t b[2] = {0, 0};
  if (int e = bus_.write_read(address_, &kRegConfig, 1, b, 2)) return e;
  return (b[1] & 0x1F) == (kConfigReset & 0x1F) ? 0 : EPROTO;
}

int Device::start(int channel) {
  const std::uint16_t w = single_shot_word(channel, pga_, dr_);
  const std::uint8_t b[3] = {kRegConfig, static_cast<std::uint8_t>(w >> 8),
                             static_cast<std::uint8_t>(w & 0xFF)};
  return bus_.write(address_, b, 3);
}

int Device::read(std::uint16_t& raw) {
  std::uint8_t b[2] = {0, 0};
  if (int e = bus_.write_read(address_, &kRegConversion, 1, b, 2)) return e;
  raw = static_cast<std::uint16_t>((b[0] << 8) | b[1]);
  return 0;
}

}  // namespace tiller::sensors::ads1115
