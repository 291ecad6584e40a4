#include "i2c/transport.hpp"

#include <cerrno>
#include <cstring>

namespace tiller::i2c {

bool is_bus_error(int err) {
  return err == ENXIO || err == EREMOTEIO || err == EIO || err == ETIMEDOUT || err == EAGAIN ||
         err == ENODEV;
}

std::string describe_errno(int err) {
  switch (err) {
    case 0:
      return "ok";
    case ENXIO:
      return "ENXIO (no ACK: nothing answers at that address)";
    case EREMOTEIO:
      return "EREMOTEIO (no ACK from the device)";
    case EIO:
      return "EIO (bus error)";
    case ETIMEDOUT:
      return "ETIMEDOUT (bus timeout, SCL held low?)";
    case EAGAIN:
      return "EAGAIN (arbitration lost)";
    case EBUSY:
      return "EBUSY (a kernel driver owns that address)";
    case ENODEV:
      return "ENODEV (the bus adapter went away)";
    case ENOENT:
      return "ENOENT (no such I2C bus: is the i2c-dev module loaded? `ls /dev/i2c-*`)";
    case EACCES:
      return "EACCES (no permission on the I2C bus: the user needs the `i2c` group)";
    case EOPNOTSUPP:
      return "EOPNOTSUPP (the adapter does not do plain I2C transfers)";
    default:
      return std::string(std::strerror(err));
  }
}

}  // namespace tiller::i2c
