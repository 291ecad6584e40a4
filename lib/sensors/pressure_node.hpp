// tiller-pressure's logic: an MS5837 (30BA or 02BA) on I2C -> pressure_t (Pa, degC, depth m)
// on TILLER_PRESSURE at rate_hz.
//
// The node ticks at twice the sample rate and alternates conversions without blocking: each
// tick reads the conversion started at the previous tick (D2 temperature, then D1 pressure) and
// starts the next one, so a tick period must exceed the OSR's conversion time (checked at
// load). Depth = (P - surface_pressure) / (water_density * 9.80665).
// Device health (sensors/device_health.hpp): a failed transaction is retried once at once
// ("bus.retries"); a second failure counts "bus.errors" and drops that conversion; `fault_after`
// failed ticks in a row, a missing device or a bad PROM CRC ("prom.crc_errors") put the heartbeat
// in FAULT with a message naming the bus and the address, and the device is set up again every
// retry period. Any failure in the last second: DEGRADED. A sample whose message fails
// checks::check is dropped and counted
// ("rejected.sample.<reason>"), never published. Time comes only from the executor.
#pragma once

#include <cstdint>
#include <string>

#include <tiller/pressure_t.hpp>

#include "core/time.hpp"
#include "i2c/transport.hpp"
#include "runtime/node.hpp"
#include "sensors/device_health.hpp"
#include "sensors/ms5837.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct PressureParams {
  std::string bus = "/dev/i2c-1";
  std::uint8_t address = ms5837::kAddress;
  ms5837::Model model = ms5837::Model::ba30;
  ms5837::Osr osr = ms5837::osr_for(4096);
  double rate_hz = 20;               // samples per second (the node ticks at twice this)
  double water_density = 997;        // kg/m^3 (fresh 997, salt 1025)
  double surface_pressure = 101325;  // Pa
  std::string channel = "TILLER_PRESSURE";
  TimeUs retry_period = kUsPerSecond;
  int fault_after = 5;  // failed ticks in a row before the device counts as lost
};

// Strict loader: every error names the file, the key and what was expected.
PressureParams load_pressure_params(const config::Value& root);
PressureParams load_pressure_file(const std::string& path);

class PressureNode : public Node {
 public:
  PressureNode(const PressureParams& p, i2c::Transport& bus);
  bool device_ready() const { return ready_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  int with_retry(auto&& op);
  void lost(TimeUs now, int err, const char* step);
  void sample_failed(TimeUs now, int err, const char* step);
  void update_health(TimeUs now);

  PressureParams p_;
  i2c::Transport& bus_;
  ms5837::Device dev_;
  DeviceHealth health_;  // "ms5837-30ba on /dev/i2c-1 at 0x76"
  bool ready_ = false;
  bool converting_pressure_ = false;  // which conversion is running
  bool have_d2_ = false;
  std::uint32_t d2_ = 0;
  pressure_t msg_{};
  std::int64_t *retries_, *bus_errors_, *crc_errors_, *not_ready_, *samples_, *init_failures_;
  std::int64_t* rejected_sample_;
};

}  // namespace tiller::sensors
