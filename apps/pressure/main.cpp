// tiller-pressure: an MS5837 pressure sensor (Bar30 / Bar02) on Linux I2C -> TILLER_PRESSURE.
// A missing device or bus (no /dev/i2c-N) is said on stderr and in the heartbeat (FAULT, bus and
// address named) and retried; the process keeps running.
#include <cstdio>

#include "i2c/linux_i2c.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/pressure_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-pressure",
                       "MS5837 pressure sensor on I2C -> pressure and depth",
                       "config/sensors/pressure_bar30.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::PressureParams p = sensors::load_pressure_file(args.config);
    // A missing bus (no /dev/i2c-N yet) is a FAULT like a missing device: said, retried.
    i2c::LinuxI2c bus(p.bus, i2c::LinuxI2c::IfMissing::kRetry);
    if (!bus.is_open())
      std::fprintf(stderr, "tiller-pressure: %s; FAULT in the heartbeat, retrying\n",
                   bus.open_error().c_str());
    sensors::PressureNode node(p, bus);
    std::fprintf(stderr, "tiller-pressure: %s at 0x%02x, OSR %d, %.0f Hz, water %.0f kg/m^3\n",
                 p.bus.c_str(), p.address, p.osr.ratio, p.rate_hz, p.water_density);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
