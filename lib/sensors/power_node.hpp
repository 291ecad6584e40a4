// tiller-power's logic: a TI INA226 on I2C across the main battery's shunt -> power_t on
// TILLER_POWER (bus voltage V, current A with + = discharge, power W, charge Ah and energy Wh
// drawn since start) at rate_hz.
//
// Set-up (one tick, no waits): MANUFACTURER_ID must read 0x5449 and DIE_ID 0x2260; then a reset
// (configuration bit 15), the configuration word (averaging, conversion times, continuous shunt
// and bus) and CAL = trunc(0.00512 / (current_lsb * shunt_ohm)), each read back. Sampling
// starts one averaged conversion later. A tick reads bus voltage, current, power and the
// calibration register; a calibration that no longer reads back (the chip lost power and came
// back with CAL = 0, which would read 0 A) is counted in "device.resets" and set up again.
// The power register is unsigned; it gets the current's sign. Charge and energy are integrated
// over the tick times (ina226::Integrator; a gap over max_gap_s is counted in "charge.gaps").
// Device health (sensors/device_health.hpp): one retry at once ("bus.retries"), then
// "bus.errors"; `fault_after` failed ticks in a row, no answer or wrong ids: FAULT naming the bus
// and the address, set up again every retry period; failures in the last second: DEGRADED.
#pragma once

#include <cstdint>
#include <string>

#include <tiller/power_t.hpp>

#include "core/time.hpp"
#include "i2c/transport.hpp"
#include "runtime/node.hpp"
#include "sensors/device_health.hpp"
#include "sensors/ina226.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct PowerParams {
  std::string bus = "/dev/i2c-1";
  std::uint8_t address = 0x40;
  double shunt_ohm = 0.002;
  double current_lsb = 0.001;  // A per LSB of the current register
  int averaging = 16;
  int bus_conversion_us = 1100;
  int shunt_conversion_us = 1100;
  double rate_hz = 10;
  bool invert_current = false;  // shunt wired so that discharge reads negative
  std::string channel = "TILLER_POWER";
  TimeUs max_gap = kUsPerSecond;
  TimeUs retry_period = kUsPerSecond;
  int fault_after = 5;
  std::uint16_t calibration = 2560;  // derived
  std::uint16_t config = 0;          // derived
};

// Strict loader: every error names the file, the key and what was expected.
PowerParams load_power_params(const config::Value& root);
PowerParams load_power_file(const std::string& path);

// One sample into `msg` (V, A, W at `now`), charge and energy integrated (a gap counted in
// `gaps`); shared by the INA226 and ADS1115 nodes. No allocation.
void fill_power_sample(power_t& msg, ina226::Integrator& integ, std::int64_t& gaps, TimeUs now,
                       double volts, double amps, double watts);

class PowerNode : public Node {
 public:
  PowerNode(const PowerParams& p, i2c::Transport& bus);
  bool device_ready() const { return ready_; }
  const ina226::Integrator& integrator() const { return integ_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  int read16(std::uint8_t reg, std::uint16_t& v);
  int write16(std::uint8_t reg, std::uint16_t v);
  int with_retry(auto&& op);
  void lost(TimeUs now, int err, std::string_view why);
  void set_up(TimeUs now);
  void sample(TimeUs now);

  PowerParams p_;
  i2c::Transport& bus_;
  DeviceHealth health_;   // "ina226 on /dev/i2c-1 at 0x40"
  std::string degraded_;  // the status while bus errors are recent (built once)
  bool ready_ = false;
  TimeUs next_step_ = INT64_MIN;  // the next sample
  ina226::Integrator integ_;
  power_t msg_{};
  std::int64_t *retries_, *bus_errors_, *init_failures_, *resets_, *gaps_, *samples_, *rejected_;
};

}  // namespace tiller::sensors
