// tiller-power: an INA226 power monitor on Linux I2C -> TILLER_POWER (V, A, W, Ah, Wh).
// A missing device or bus (no /dev/i2c-N) is said in the heartbeat (FAULT, bus and address named)
// and retried; the process keeps running.
#include <cstdio>

#include "i2c/linux_i2c.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/power_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-power",
                       "INA226 power monitor on I2C -> battery voltage, current, charge used",
                       "config/sensors/power_ina226.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::PowerParams p = sensors::load_power_file(args.config);
    // A missing bus (no /dev/i2c-N yet) is a FAULT like a missing device: said, retried.
    i2c::LinuxI2c bus(p.bus, i2c::LinuxI2c::IfMissing::kRetry);
    if (!bus.is_open())
      std::fprintf(stderr, "tiller-power: %s; FAULT in the heartbeat, retrying\n",
                   bus.open_error().c_str());
    sensors::PowerNode node(p, bus);
    std::fprintf(stderr, "tiller-power: %s at 0x%02x, shunt %g ohm, CAL %u, %.0f Hz\n",
                 p.bus.c_str(), p.address, p.shunt_ohm, p.calibration, p.rate_hz);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
