// tiller-navigator --calibrate-compass S: records the compass for S seconds while the vehicle is
// turned through every attitude it can take, fits the hard- and soft-iron correction
// (ahrs::fit_ellipsoid) and prints the `compass_calibration:` block for the navigator config, or
// why the recording is not enough. No LCM: nothing is published while calibrating.
#pragma once

#include "i2c/transport.hpp"
#include "sensors/navigator_node.hpp"
#include "spi/transport.hpp"

namespace tiller {
int calibrate_compass(const sensors::NavigatorParams& p, spi::Transport& spi, i2c::Transport& i2c,
                      double seconds);
}  // namespace tiller
