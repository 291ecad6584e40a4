// The configs the end-to-end test and the latency benchmark start the stack with (relative to
// the source tree): seed 000's ROV, the ESC's sim backend (TILLER_ESC_OUTPUT is what it would
// write on the I2C bus, as int16 throttles).
#pragma once

namespace tiller::e2e {
inline constexpr const char* kMixerConfig = "config/mixer/seed000_rov4.yaml";
inline constexpr const char* kEscConfig = "config/esc/seed000_sim.yaml";
}  // namespace tiller::e2e
