// tiller-imu: a BNO055 (fusing AHRS) on Linux I2C -> TILLER_IMU and TILLER_HEADING.
// A missing device or bus (no /dev/i2c-N) is said in the heartbeat (FAULT, bus and address named)
// and retried; the process keeps running.
#include <cstdio>

#include "i2c/linux_i2c.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/imu_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-imu",
                       "BNO055 IMU on I2C -> body rates, specific force, orientation, heading",
                       "config/sensors/imu_bno055.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::ImuParams p = sensors::load_imu_file(args.config);
    // A missing bus (no /dev/i2c-N yet) is a FAULT like a missing device: said, retried.
    i2c::LinuxI2c bus(p.bus, i2c::LinuxI2c::IfMissing::kRetry);
    if (!bus.is_open())
      std::fprintf(stderr, "tiller-imu: %s; FAULT in the heartbeat, retrying\n",
                   bus.open_error().c_str());
    sensors::ImuNode node(p, bus);
    std::fprintf(stderr, "tiller-imu: %s at 0x%02x, %.0f Hz, heading %s\n", p.bus.c_str(),
                 p.address, p.rate_hz, p.true_north ? "true" : "magnetic");
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
