// tiller-power: the main battery's power monitor on Linux I2C -> TILLER_POWER (V, A, W, Ah, Wh):
// an INA226 (`device: ina226`, the default; sensors/power_node.hpp) or a power module on an
// ADS1115 ADC, the Navigator's (`device: ads1115`; sensors/ads1115_power_node.hpp). A missing
// device or bus (no /dev/i2c-N) is said in the heartbeat (FAULT, bus and address named) and
// retried; the process keeps running.
#include <cstdio>
#include <memory>

#include "core/config.hpp"
#include "i2c/linux_i2c.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/ads1115_power_node.hpp"
#include "sensors/power_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-power",
                       "INA226 or ADS1115 power module on I2C -> battery voltage, current, "
                       "charge used",
                       "config/sensors/power_ina226.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const config::Value root = config::Value::load_file(args.config);
    const bool ads = root.string_or("device", "ina226") == "ads1115";
    std::unique_ptr<Node> node;
    std::unique_ptr<i2c::LinuxI2c> bus;
    if (ads) {
      const auto p = sensors::load_ads1115_power_params(root);
      bus = std::make_unique<i2c::LinuxI2c>(p.bus, i2c::LinuxI2c::IfMissing::kRetry);
      node = std::make_unique<sensors::Ads1115PowerNode>(p, *bus);
      std::fprintf(stderr, "tiller-power: ads1115 on %s at 0x%02x, AIN%d x %g V/V, AIN%d %g A/V\n",
                   p.bus.c_str(), p.address, p.module.voltage_channel, p.module.voltage_divider,
                   p.module.current_channel, p.module.amps_per_volt);
    } else {
      const auto p = sensors::load_power_params(root);
      bus = std::make_unique<i2c::LinuxI2c>(p.bus, i2c::LinuxI2c::IfMissing::kRetry);
      node = std::make_unique<sensors::PowerNode>(p, *bus);
      std::fprintf(stderr, "tiller-power: %s at 0x%02x, shunt %g ohm, CAL %u, %.0f Hz\n",
                   p.bus.c_str(), p.address, p.shunt_ohm, p.calibration, p.rate_hz);
    }
    // A missing bus (no /dev/i2c-N yet) is a FAULT like a missing device: said, retried.
    if (!bus->is_open())
      std::fprintf(stderr, "tiller-power: %s; FAULT in the heartbeat, retrying\n",
                   bus->open_error().c_str());
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(*node);
    return ex.run();
  });
}
