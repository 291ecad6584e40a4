// The real SPI transport: a Linux spidev device (/dev/spidevB.C, one chip select).
//
// Set-up (once, at open): SPI_IOC_WR_MODE (mode 0..3; the ICM-20602 takes mode 0 or 3),
// SPI_IOC_WR_BITS_PER_WORD 8 and SPI_IOC_WR_MAX_SPEED_HZ; each transfer is one
// SPI_IOC_MESSAGE(1) ioctl (struct spi_ioc_transfer: tx_buf, rx_buf, len, speed_hz), chip
// select held for the whole transfer. Needs the kernel's spidev driver (on a Raspberry Pi:
// dtparam=spi=on, and dtoverlay=spi1-3cs for SPI1, docs/bring-up.md) and read/write access to
// the node (group spi). Cannot run on the build machine (no /dev/spidev*); tests use FakeSpi.
// A missing device is kept as open_error() and the open is tried again on each transfer, which
// returns the open's errno until it works (a sensor missing is a FAULT, not an exit).
#pragma once

#include <cstdint>
#include <string>

#include "spi/transport.hpp"

namespace tiller::spi {

class LinuxSpi : public Transport {
 public:
  LinuxSpi(const std::string& path, std::uint8_t mode, std::uint32_t speed_hz);
  ~LinuxSpi() override;
  LinuxSpi(const LinuxSpi&) = delete;
  LinuxSpi& operator=(const LinuxSpi&) = delete;

  int transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n) override;
  void wait_us(std::int64_t us) override;
  std::string name() const override { return path_; }

  bool is_open() const { return fd_ >= 0; }
  // Why the device could not be opened at construction, with what to check ("" when it was).
  const std::string& open_error() const { return open_error_; }

 private:
  int open_device();  // 0 or the errno; allocates nothing
  std::string path_;
  std::uint8_t mode_;
  std::uint32_t speed_hz_;
  int fd_ = -1;
  std::string open_error_;
};

}  // namespace tiller::spi
