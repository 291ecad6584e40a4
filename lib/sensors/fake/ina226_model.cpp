#include "sensors/fake/ina226_model.hpp"

#include <cerrno>

#include "sensors/ina226.hpp"

namespace tiller::sensors::fake {

using namespace ina226;

void Ina226Model::power_cycle() {
  config_ = kConfigPowerOn;
  calibration_ = mask_ = alert_ = 0;
}

std::uint16_t Ina226Model::reg(std::uint8_t r) const {
  // Data sheet equations 3 and 4, in the chip's integer arithmetic.
  const std::int32_t current = static_cast<std::int16_t>(shunt) * calibration_ / 2048;
  const std::int64_t abs_current = current < 0 ? -current : current;
  switch (r) {
    case kRegConfig:
      return config_;
    case kRegShunt:
      return shunt;
    case kRegBus:
      return bus;
    case kRegPower:
      return static_cast<std::uint16_t>(abs_current * bus / 20000);
    case kRegCurrent:
      return static_cast<std::uint16_t>(static_cast<std::int16_t>(current));
    case kRegCalibration:
      return calibration_;
    case kRegMaskEnable:
      return mask_;
    case kRegAlertLimit:
      return alert_;
    case kRegManufacturerId:
      return manufacturer_id;
    case kRegDieId:
      return kDieId;
    default:
      return 0;
  }
}

int Ina226Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs) {
  if (n == 0) return EIO;
  ptr_ = d[0];
  if (n == 1) return 0;  // a pointer write before a read
  if (n != 3) return EIO;
  const auto v = static_cast<std::uint16_t>(d[1] << 8 | d[2]);
  switch (ptr_) {
    case kRegConfig:
      if (v & kConfigReset) {
        ++resets_;
        power_cycle();
      } else {
        config_ = static_cast<std::uint16_t>(v | 0x4000);  // bit 14 always reads 1
      }
      return 0;
    case kRegCalibration:
      calibration_ = v & 0x7FFF;  // bit 15 is not used
      return 0;
    case kRegMaskEnable:
      mask_ = v;
      return 0;
    case kRegAlertLimit:
      alert_ = v;
      return 0;
    default:
      return 0;  // read-only registers ignore writes
  }
}

int Ina226Model::on_read(std::uint8_t* out, std::size_t n, TimeUs) {
  if (n != 2) return EIO;
  const std::uint16_t v = reg(ptr_);
  out[0] = static_cast<std::uint8_t>(v >> 8);
  out[1] = static_cast<std::uint8_t>(v);
  return 0;
}

}  // namespace tiller::sensors::fake
