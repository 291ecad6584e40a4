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
    default:
      return std::string(std::strerror(err));
  }
}

}  // namespace tiller::i2c
