#include "calibrate_compass.hpp"

#include <chrono>
#include <cstdio>
#include <thread>

#include "ahrs/compass_calibration.hpp"
#include "runtime/node.hpp"

namespace tiller {

namespace {
struct NoBus : Bus {
  void publish(std::string_view, const std::uint8_t*, int) override {}
};
}  // namespace

int calibrate_compass(const sensors::NavigatorParams& p, spi::Transport& spi, i2c::Transport& i2c,
                      double seconds) {
  sensors::NavigatorNode node(p, spi, i2c);
  NoBus bus;
  node.attach(&bus);
  node.record_compass(static_cast<std::size_t>(seconds * p.rate_hz) + 16);
  std::fprintf(stderr,
               "tiller-navigator: recording the compass for %.0f s: turn the vehicle through a "
               "full turn at several roll and pitch angles, away from steel and running motors\n",
               seconds);
  const auto start = std::chrono::steady_clock::now();
  const TimeUs period = node.tick_period();
  TimeUs said = 0;
  for (TimeUs t = 0; t <= from_seconds(seconds); t += period) {
    std::this_thread::sleep_until(start + std::chrono::microseconds(t));
    node.tick(t);
    if (t - said >= 5 * kUsPerSecond) {
      said = t;
      std::fprintf(stderr, "  %.0f s: %zu samples%s\n", to_seconds(t), node.recorded().size(),
                   node.compass_up() ? "" : " (the compass is not answering)");
    }
  }
  const ahrs::FitResult f = ahrs::fit_ellipsoid(node.recorded());
  if (!f.ok) {
    std::fprintf(stderr, "tiller-navigator: no calibration from %zu samples: %s\n",
                 node.recorded().size(), f.why.c_str());
    return 1;
  }
  std::fprintf(stderr,
               "tiller-navigator: %zu samples, field %.1f uT, residual %.2f %%, coverage %.2f\n",
               node.recorded().size(), f.radius, 100 * f.relative_residual, f.coverage);
  const auto& o = f.cal.offset;
  const auto& m = f.cal.matrix;
  std::printf(
      "compass_calibration:   # tiller-navigator --calibrate-compass: %zu samples, "
      "residual %.2f %%\n",
      node.recorded().size(), 100 * f.relative_residual);
  std::printf("  offset_ut: [%.3f, %.3f, %.3f]\n", o[0], o[1], o[2]);
  std::printf("  matrix: [%.5f, %.5f, %.5f, %.5f, %.5f, %.5f, %.5f, %.5f, %.5f]\n", m[0], m[1],
              m[2], m[3], m[4], m[5], m[6], m[7], m[8]);
  std::printf("  field_ut: %.2f\n", f.radius);
  return 0;
}

}  // namespace tiller
