// tiller-power's logic for a power module on a TI ADS1115 ADC (the Blue Robotics Navigator's ADC,
// I2C address 0x48, with the Blue Robotics Power Sense Module): power_t on TILLER_POWER (bus
// voltage V, current A with + = discharge, power W, charge Ah and energy Wh drawn since start).
//
// Scaling (ads1115::PowerModule, from config): V_bus = voltage_divider * V(AIN voltage_channel);
// I = (V(AIN current_channel) - current_offset_v) * amps_per_volt (Power Sense Module: 11.0 V/V,
// 37.8788 A/V, 0.330 V offset; the Navigator wires voltage to AIN2 and current to AIN3).
// Set-up: the config register must read like an ADS1115 (ads1115::Device::probe). Sampling,
// single-shot, never waiting in a tick: each tick reads the conversion started at the tick before
// (after ads1115::conversion_us of the data rate; a conversion not yet done, OS bit 0, is counted
// in "conversion.not_ready" and read at the next tick), then starts the other input. Voltage and
// current alternate, so a power_t goes out every second tick (rate_hz / 2), after each current.
// Charge and energy as tiller-power's INA226 node (ina226::Integrator). Device health
// (sensors/device_health.hpp): one retry at once ("bus.retries"), then "bus.errors"; fault_after
// failed ticks in a row or no answer: FAULT naming the bus and the address, probed again every
// retry period; failures in the last second: DEGRADED. A sample outside power_t's ranges is
// refused and counted ("rejected.sample.range"). No allocation after set-up.
#pragma once

#include <cstdint>
#include <string>

#include <tiller/power_t.hpp>

#include "core/time.hpp"
#include "i2c/transport.hpp"
#include "runtime/node.hpp"
#include "sensors/ads1115.hpp"
#include "sensors/device_health.hpp"
#include "sensors/ina226.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct Ads1115PowerParams {
  std::string bus = "/dev/i2c-1";
  std::uint8_t address = ads1115::kAddress;
  ads1115::PowerModule module;
  double full_scale_v = 4.096;  // the PGA's range: one of 6.144, 4.096, 2.048, 1.024, 0.512, 0.256
  int data_rate_sps = 128;      // 8, 16, 32, 64, 128, 250, 475 or 860
  double rate_hz = 20;          // ticks; a power_t every second tick
  bool invert_current = false;
  std::string channel = "TILLER_POWER";
  TimeUs max_gap = kUsPerSecond;
  TimeUs retry_period = kUsPerSecond;
  int fault_after = 5;
};

// Strict loader (`device: ads1115` files): every error names the file, the key and what was
// expected.
Ads1115PowerParams load_ads1115_power_params(const config::Value& root);

class Ads1115PowerNode : public Node {
 public:
  Ads1115PowerNode(const Ads1115PowerParams& p, i2c::Transport& bus);
  bool device_ready() const { return ready_; }
  const ina226::Integrator& integrator() const { return integ_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  int with_retry(auto&& op);
  void failed(TimeUs now, int err);
  void sample(TimeUs now);

  Ads1115PowerParams p_;
  i2c::Transport& bus_;
  ads1115::Device dev_;
  DeviceHealth health_;   // "ads1115 on /dev/i2c-1 at 0x48"
  std::string degraded_;  // the status while bus errors are recent (built once)
  bool ready_ = false;
  bool reading_current_ = false;  // the conversion under way: current (else voltage)
  TimeUs read_at_ = 0;            // when the conversion under way is done
  double bus_v_ = 0;
  bool have_voltage_ = false;
  ina226::Integrator integ_;
  power_t msg_{};
  std::int64_t *retries_, *bus_errors_, *init_failures_, *not_ready_, *gaps_, *samples_, *rejected_;
};

}  // namespace tiller::sensors
