// The I2C transport under the ESC backends and the I2C sensor drivers: one bus, 7-bit
// addresses, raw byte transactions.
//
// Implementations: LinuxI2c (i2c/linux_i2c.hpp, /dev/i2c-N through i2c-dev ioctls), the fake
// bus (i2c/fake_bus.hpp) with device models (esc/fake/fake_i2c.hpp for the ESCs,
// sensors/fake/ for the sensors) that tests and benchmarks drive, and the ESC's dry-run
// transport (esc/dry_run.hpp), which prints the bytes instead of sending them.
// Every call returns 0 on success or an errno value (ENXIO/EREMOTEIO: no ACK from the address,
// ETIMEDOUT, EAGAIN: arbitration lost, EIO); it never throws, and a failure affects only that
// transaction. Calls must not allocate (the ESC and sensor loops run them every cycle).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/time.hpp"

namespace tiller::i2c {

class Transport {
 public:
  virtual ~Transport() = default;

  // Writes n bytes to `addr` as one transaction (START, addr+W, bytes, STOP).
  virtual int write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) = 0;
  // Writes wn bytes then reads rn bytes in one combined transaction (repeated START).
  virtual int write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                         std::size_t rn) = 0;
  // Checks that `addr` may be used (on Linux: no kernel driver owns it). 0 or an errno.
  virtual int claim(std::uint8_t addr) {
    (void)addr;
    return 0;
  }
  // Blocks for `us` microseconds (device settling times, e.g. the PCA9685's 500 us after
  // waking; an MS5837 reset). Used at start-up, and in a cycle only to set up again a PCA9685 that
  // appeared late or came back asleep after a brown-out (at most once a second; that cycle is 0.5
  // ms late). Fakes advance their model clock.
  virtual void wait_us(std::int64_t us) = 0;
  // Tells the transport the executor's time before a cycle's transactions (fakes drive their
  // device models with it; the Linux transport ignores it).
  virtual void set_time(TimeUs now) { (void)now; }
  // The bus, for messages and the status message (e.g. "/dev/i2c-1").
  virtual std::string name() const = 0;
};

// One register write: [reg, value] to `addr` (the 8-bit register maps of the sensor chips).
inline int write_reg(Transport& bus, std::uint8_t addr, std::uint8_t reg, std::uint8_t value) {
  const std::uint8_t b[2] = {reg, value};
  return bus.write(addr, b, 2);
}

// True for the errno values an I2C bus reports for a transaction that failed on the wire
// (as opposed to a programming error such as EINVAL or EBADF).
bool is_bus_error(int err);
// "ENXIO (no ACK: nothing at that address)" etc., for messages.
std::string describe_errno(int err);

}  // namespace tiller::i2c
