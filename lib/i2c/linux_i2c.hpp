// The real I2C transport: a Linux i2c-dev adapter (/dev/i2c-N).
//
// Every transaction is one I2C_RDWR ioctl (a write: one message; write-then-read: two messages
// joined by a repeated START), so switching between addresses costs no extra system call.
// claim(addr) does ioctl(I2C_SLAVE, addr) once at start: EBUSY there means a kernel driver owns
// the address. Needs the kernel's i2c-dev module and read/write access to the device node. This
// code cannot run on the build machine (no /dev/i2c-*); tests use i2c/fake_bus.hpp.
#pragma once

#include <string>

#include "i2c/transport.hpp"

namespace tiller::i2c {

class LinuxI2c : public Transport {
 public:
  // Opens the adapter; throws std::runtime_error saying what to check if it cannot.
  explicit LinuxI2c(const std::string& path);
  ~LinuxI2c() override;
  LinuxI2c(const LinuxI2c&) = delete;
  LinuxI2c& operator=(const LinuxI2c&) = delete;

  int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) override;
  int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                 std::size_t rn) override;
  int claim(std::uint8_t addr) override;
  void wait_us(std::int64_t us) override;
  std::string name() const override { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace tiller::i2c
