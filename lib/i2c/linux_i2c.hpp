// The real I2C transport: a Linux i2c-dev adapter (/dev/i2c-N).
//
// Every transaction is one I2C_RDWR ioctl (a write: one message; write-then-read: two messages
// joined by a repeated START), so switching between addresses costs no extra system call.
// claim(addr) does ioctl(I2C_SLAVE, addr) once at start: EBUSY there means a kernel driver owns
// the address. Needs the kernel's i2c-dev module and read/write access to the device node. This
// code cannot run on the build machine (no /dev/i2c-*); tests use i2c/fake_bus.hpp.
// IfMissing::kThrow (the ESC driver: no bus, no run) throws when the adapter cannot be opened;
// kRetry (the sensor drivers: a sensor missing is a FAULT in the heartbeat, the process keeps
// running) keeps going closed and opens it again on the next transaction, which returns the
// open's errno (ENOENT: no such bus) until it can.
#pragma once

#include <string>

#include "i2c/transport.hpp"

namespace tiller::i2c {

class LinuxI2c : public Transport {
 public:
  enum class IfMissing { kThrow, kRetry };
  // Opens the adapter; throws std::runtime_error saying what to check if it cannot (kThrow), or
  // keeps the reason in open_error() and tries again on each transaction (kRetry).
  explicit LinuxI2c(const std::string& path, IfMissing if_missing = IfMissing::kThrow);
  ~LinuxI2c() override;
  LinuxI2c(const LinuxI2c&) = delete;
  LinuxI2c& operator=(const LinuxI2c&) = delete;

  int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) override;
  int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                 std::size_t rn) override;
  int claim(std::uint8_t addr) override;
  void wait_us(std::int64_t us) override;
  std::string name() const override { return path_; }

  bool is_open() const { return fd_ >= 0; }
  // Why the adapter could not be opened at construction, with what to check ("" when it was).
  const std::string& open_error() const { return open_error_; }

 private:
  // Opens the adapter: 0, or the errno (EOPNOTSUPP: an adapter without plain I2C transfers).
  // No allocation (it runs in a transaction when the bus was missing).
  int open_adapter();
  int ensure_open() { return fd_ >= 0 ? 0 : open_adapter(); }

  enum class Step { kOpen, kFuncs, kPlainI2c };
  std::string path_;
  int fd_ = -1;
  Step failed_at_ = Step::kOpen;  // where the last open_adapter() that failed stopped
  std::string open_error_;
};

}  // namespace tiller::i2c
