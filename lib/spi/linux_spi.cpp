#include "spi/linux_spi.hpp"

#include <fcntl.h>
#include <linux/spi/spidev.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace tiller::spi {

int LinuxSpi::open_device() {
  const int fd = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return errno;
  std::uint8_t bits = 8;
  if (::ioctl(fd, SPI_IOC_WR_MODE, &mode_) < 0 ||
      ::ioctl(fd, SPI_IOC_WR_BITS_PER_WORD, &bits) < 0 ||
      ::ioctl(fd, SPI_IOC_WR_MAX_SPEED_HZ, &speed_hz_) < 0) {
    const int e = errno;
    ::close(fd);
    return e;
  }
  fd_ = fd;
  return 0;
}

LinuxSpi::LinuxSpi(const std::string& path, std::uint8_t mode, std::uint32_t speed_hz)
    : path_(path), mode_(mode), speed_hz_(speed_hz) {
  const int e = open_device();
  if (e == 0) return;
  std::string hint;
  if (e == ENOENT)
    hint =
        " (is SPI enabled? on a Raspberry Pi: dtparam=spi=on and, for the Navigator's SPI1, "
        "dtoverlay=spi1-3cs in /boot/config.txt; `ls /dev/spidev*` lists the devices)";
  else if (e == EACCES || e == EPERM)
    hint = " (add the user to the group that owns it, usually `spi`, or run as root)";
  open_error_ = "cannot open SPI device " + path + ": " + std::strerror(e) + hint;
}

LinuxSpi::~LinuxSpi() {
  if (fd_ >= 0) ::close(fd_);
}

int LinuxSpi::transfer(const std::uint8_t* tx, std::uint8_t* rx, std::size_t n) {
  if (fd_ < 0) {
    if (const int e = open_device()) return e;
  }
  spi_ioc_transfer t{};
  t.tx_buf = reinterpret_cast<std::uintptr_t>(tx);
  t.rx_buf = reinterpret_cast<std::uintptr_t>(rx);
  t.len = static_cast<__u32>(n);
  t.speed_hz = speed_hz_;
  t.bits_per_word = 8;
  return ::ioctl(fd_, SPI_IOC_MESSAGE(1), &t) < 0 ? errno : 0;
}

void LinuxSpi::wait_us(std::int64_t us) {
  timespec ts{static_cast<time_t>(us / 1'000'000), static_cast<long>((us % 1'000'000) * 1000)};
  while (::nanosleep(&ts, &ts) < 0 && errno == EINTR) {
  }
}

}  // namespace tiller::spi
