// tiller-power: an INA226 power monitor on Linux I2C -> TILLER_POWER (V, A, W, Ah, Wh).
// A missing device is said in the heartbeat (FAULT, bus and address named) and retried; the
// process keeps running.
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
    i2c::LinuxI2c bus(p.bus);
    sensors::PowerNode node(p, bus);
    std::fprintf(stderr, "tiller-power: %s at 0x%02x, shunt %g ohm, CAL %u, %.0f Hz\n",
                 p.bus.c_str(), p.address, p.shunt_ohm, p.calibration, p.rate_hz);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
