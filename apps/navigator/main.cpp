// tiller-navigator: the Blue Robotics Navigator's ICM-20602 (SPI) and AK09915 (I2C) through the
// AHRS -> TILLER_IMU and TILLER_HEADING (sensors/navigator_node.hpp). A missing bus or device is
// said in the heartbeat (FAULT or DEGRADED, the device named) and retried; the process keeps
// running. --calibrate-compass S records the compass instead and prints its calibration
// (calibrate_compass.hpp).
#include <cstdio>
#include <cstdlib>

#include "calibrate_compass.hpp"

#include "i2c/linux_i2c.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/navigator_node.hpp"
#include "spi/linux_spi.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-navigator",
                       "Navigator IMU and compass through the AHRS -> rates, attitude, heading",
                       "config/sensors/navigator.yaml",
                       {{"calibrate-compass", "S",
                         "record the compass S seconds while the vehicle is turned, print its "
                         "compass_calibration block, exit (no LCM)",
                         ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::NavigatorParams p = sensors::load_navigator_file(args.config);
    spi::LinuxSpi spi(p.spi, 0, p.spi_speed_hz);
    if (!spi.is_open())
      std::fprintf(stderr, "tiller-navigator: %s; FAULT in the heartbeat, retrying\n",
                   spi.open_error().c_str());
    i2c::LinuxI2c i2c(p.i2c, i2c::LinuxI2c::IfMissing::kRetry);
    if (!i2c.is_open())
      std::fprintf(stderr, "tiller-navigator: %s; no heading until it opens\n",
                   i2c.open_error().c_str());
    if (!args.get("calibrate-compass").empty())
      return calibrate_compass(
          p, spi, i2c,
          app::number_option(args, "calibrate-compass", 10, 3600, "seconds in [10, 3600]"));
    sensors::NavigatorNode node(p, spi, i2c);
    std::fprintf(stderr, "tiller-navigator: %s and %s at 0x%02x, %.0f Hz, heading %s\n",
                 p.spi.c_str(), p.i2c.c_str(), p.compass_address, p.rate_hz,
                 p.true_north ? "true" : "magnetic");
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
