#include "sensors/fake/bno055_model.hpp"

#include <cerrno>

#include "sensors/bno055.hpp"

namespace tiller::sensors::fake {

using namespace bno055;

Bno055Model::Bno055Model() {
  power_cycle();
}

void Bno055Model::power_cycle() {
  regs_.fill(0);
  regs_[kRegChipId] = chip_id;
  regs_[0x01] = 0xFB;  // ACC_ID
  regs_[0x02] = 0x32;  // MAG_ID
  regs_[0x03] = 0x0F;  // GYR_ID
  regs_[kRegUnitSel] = 0x80;
  regs_[kRegOprMode] = kModeConfig;
  ptr_ = 0;
}

void Bno055Model::set_vector(std::uint8_t reg, std::int16_t x, std::int16_t y, std::int16_t z) {
  const std::int16_t v[3] = {x, y, z};
  for (int i = 0; i < 3; ++i) {
    data_[reg + 2 * i] = static_cast<std::uint8_t>(v[i] & 0xFF);
    data_[reg + 2 * i + 1] = static_cast<std::uint8_t>((v[i] >> 8) & 0xFF);
  }
}

void Bno055Model::set_quaternion(std::int16_t w, std::int16_t x, std::int16_t y, std::int16_t z) {
  const std::int16_t v[4] = {w, x, y, z};
  for (int i = 0; i < 4; ++i) {
    data_[kRegQuaData + 2 * i] = static_cast<std::uint8_t>(v[i] & 0xFF);
    data_[kRegQuaData + 2 * i + 1] = static_cast<std::uint8_t>((v[i] >> 8) & 0xFF);
  }
}

void Bno055Model::set_euler(std::int16_t heading, std::int16_t roll, std::int16_t pitch) {
  set_vector(kRegEulData, heading, roll, pitch);
}

int Bno055Model::on_write(const std::uint8_t* d, std::size_t n, TimeUs now) {
  if (n == 0) return EIO;
  ptr_ = d[0];
  for (std::size_t i = 1; i < n; ++i, ++ptr_) {
    const std::uint8_t r = ptr_ & 0x7F;
    const bool config = regs_[kRegOprMode] == kModeConfig;
    if (r == kRegOprMode) {
      regs_[r] = d[i] & 0x0F;
      if (regs_[r] != kModeConfig) running_at_ = now + kFromConfigUs;
    } else if (config &&
               (r == kRegPageId || r == kRegUnitSel || r == kRegPwrMode || r == kRegSysTrigger)) {
      if (r == kRegSysTrigger && (d[i] & 0x20)) {  // RST_SYS
        power_cycle();
        return 0;
      }
      regs_[r] = d[i];
    }
  }
  return 0;
}

std::uint8_t Bno055Model::read_reg(std::uint8_t r, TimeUs now) const {
  const bool running = regs_[kRegOprMode] != kModeConfig && now >= running_at_;
  if (r >= kRegAccData && r < kRegTemp) return running ? data_[r] : 0;
  if (r == kRegTemp) return running ? temp : 0;
  if (r == kRegCalibStat) return running ? calib_stat : 0;
  if (r == kRegSysStatus) {
    if (!running) return 0;
    return sys_err != 0 ? kSysStatusError : kSysStatusFusionRunning;
  }
  if (r == kRegSysErr) return running ? sys_err : 0;
  return regs_[r & 0x7F];
}

int Bno055Model::on_read(std::uint8_t* out, std::size_t n, TimeUs now) {
  if (ptr_ == kRegAccData && n == kBurstBytes) ++data_reads_;
  for (std::size_t i = 0; i < n; ++i, ++ptr_) out[i] = read_reg(ptr_, now);
  return 0;
}

}  // namespace tiller::sensors::fake
