// The SPI transport under the SPI sensor drivers (the Navigator's ICM-20602): one chip select of
// one bus (Linux names it /dev/spidevB.C), full-duplex byte transfers with the chip selected for
// the whole transfer.
//
// Implementations: LinuxSpi (spi/linux_spi.hpp, spidev's SPI_IOC_MESSAGE ioctl) and FakeSpi
// (spi/fake_spi.hpp) with a device model that tests and benchmarks drive. Every call returns 0 or
// an errno value; it never throws and never allocates (a sensor loop runs it every tick).
// Register convention of the InvenSense parts (ICM-20602 datasheet, "SPI interface"): the first
// byte is the register address with bit 7 set for a read (0x80 | reg) and clear for a write; the
// bytes clocked in after it are the register contents (auto-increment).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/time.hpp"

namespace tiller::spi {

class Transport {
 public:
  virtual ~Transport() = default;
  // One transfer of n bytes: tx out, rx in (rx may be null). 0 or an errno.
  virtual int transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n) = 0;
  // Blocks for `us` microseconds (a reset's settling time at set-up). Fakes advance their clock.
  virtual void wait_us(std::int64_t us) = 0;
  // The executor's time before a tick's transfers (fakes drive their model with it).
  virtual void set_time(TimeUs now) { (void)now; }
  // "/dev/spidev1.0", for messages.
  virtual std::string name() const = 0;

  // Register helpers on top of transfer() (bit 7 = read). n <= 32 for read_regs.
  int write_reg(std::uint8_t reg, std::uint8_t value);
  int read_regs(std::uint8_t reg, std::uint8_t* out, std::size_t n);
};

inline constexpr std::uint8_t kReadBit = 0x80;
inline constexpr std::size_t kMaxBurst = 32;

}  // namespace tiller::spi
