// tiller-imu's logic: a BNO055 on I2C in a fusion mode -> imu_t on TILLER_IMU (body FRD rates
// in rad/s, specific force in m/s^2, orientation body -> NED, calibration levels) and the fused
// yaw as heading_t on TILLER_HEADING, at rate_hz.
//
// Set-up never blocks: a tick reads CHIP_ID (0xA0) and selects CONFIGMODE, a tick at least
// 19 ms later writes PAGE_ID, PWR_MODE, UNIT_SEL and the fusion OPR_MODE, and one at least
// 7 ms after that starts sampling (one 54-byte burst from 0x08 a tick). A burst whose UNIT_SEL
// or OPR_MODE differ from what was written means the chip reset itself ("device.resets"): it is
// set up again at once. orientation_valid needs the fusion running (SYS_STATUS 5), a unit
// quaternion and a system calibration level >= min_system_calibration; heading_t is sent only
// then. SYS_STATUS 1 (system error) is a FAULT naming SYS_ERR.
// Device health (sensors/device_health.hpp): one retry at once ("bus.retries"), then
// "bus.errors"; `fault_after` failed ticks in a row, no answer or a wrong chip id: FAULT with the
// bus and the address in the status, set up again every retry period; failures in the last second
// or an uncalibrated fusion: DEGRADED. Time comes only from the executor.
#pragma once

#include <cstdint>
#include <string>

#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>

#include "core/time.hpp"
#include "i2c/transport.hpp"
#include "runtime/node.hpp"
#include "sensors/bno055.hpp"
#include "sensors/device_health.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct ImuParams {
  std::string bus = "/dev/i2c-1";
  std::uint8_t address = bno055::kAddressA;
  std::uint8_t mode = bno055::kModeNdof;  // NDOF or NDOF_FMC_OFF
  double rate_hz = 50;                    // at most 100 (the fusion's output rate)
  bno055::Mount mount;
  bool true_north = false;  // a declination was configured: heading is true, not magnetic
  double declination = 0;   // rad, east positive (true = magnetic + declination)
  int min_system_calibration = 1;
  double angular_rate_std = 0;    // rad/s, 1 sigma per axis (0: not known)
  double specific_force_std = 0;  // m/s^2 (0: not known)
  double orientation_std = 0;     // rad (0: not known)
  double heading_std = 0;         // rad (0: not known)
  std::string imu_channel = "TILLER_IMU";
  std::string heading_channel = "TILLER_HEADING";
  bool publish_heading = true;
  TimeUs retry_period = kUsPerSecond;
  int fault_after = 5;
};

// A `mount: {forward: +y, right: +x, down: -z}` block (which signed chip axis lies along each
// body axis); also tiller-navigator's.
bno055::Mount load_mount(const config::Value& m);
// Strict loader: every error names the file, the key and what was expected.
ImuParams load_imu_params(const config::Value& root);
ImuParams load_imu_file(const std::string& path);

class ImuNode : public Node {
 public:
  ImuNode(const ImuParams& p, i2c::Transport& bus);
  bool device_ready() const { return state_ == State::running; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  enum class State { down, configuring, starting, running };
  int write_reg(std::uint8_t reg, std::uint8_t value);
  int with_retry(auto&& op);
  void lost(TimeUs now, int err, std::string_view why);
  void set_up(TimeUs now);
  void sample(TimeUs now);
  void update_health(TimeUs now, const bno055::Raw* raw);
  void say(std::int8_t state, int key, auto&& make);

  ImuParams p_;
  i2c::Transport& bus_;
  DeviceHealth health_;  // "bno055 on /dev/i2c-1 at 0x28"
  State state_ = State::down;
  TimeUs next_step_ = INT64_MIN;  // the next set-up step
  bno055::Burst burst_{};
  imu_t imu_{};
  heading_t heading_{};
  std::int64_t *retries_, *bus_errors_, *init_failures_, *resets_, *device_errors_;
  std::int64_t *not_fusing_, *uncalibrated_, *samples_, *headings_, *rejected_imu_,
      *rejected_heading_;
  std::string status_;
  int health_key_ = 0;  // what status_ says (0: a one-off message)
};

}  // namespace tiller::sensors
