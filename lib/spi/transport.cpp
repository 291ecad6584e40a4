#include "spi/transport.hpp"

#include <cerrno>
#include <cstring>

namespace tiller::spi {

int Transport::write_reg(std::uint8_t reg, std::uint8_t value) {
  const std::uint8_t tx[2] = {static_cast<std::uint8_t>(reg & 0x7F), value};
  return transfer(tx, nullptr, 2);
}

int Transport::read_regs(std::uint8_t reg, std::uint8_t* out, std::size_t n) {
  if (n > kMaxBurst) return EINVAL;
  std::uint8_t tx[kMaxBurst + 1] = {};
  std::uint8_t rx[kMaxBurst + 1] = {};
  tx[0] = static_cast<std::uint8_t>(reg | kReadBit);
  const int err = transfer(tx, rx, n + 1);
  if (err == 0) std::memcpy(out, rx + 1, n);
  return err;
}

}  // namespace tiller::spi
