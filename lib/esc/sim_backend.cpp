#include "esc/sim_backend.hpp"

#include <tiller/esc_output_t.hpp>

namespace tiller::esc {

SimBackend::SimBackend(std::vector<EscChannelParams> escs, bool pulse_us)
    : EscBackend(std::move(escs)), pulse_us_(pulse_us) {
  label_ = "sim";
}

std::int8_t SimBackend::unit() const {
  return pulse_us_ ? esc_output_t::UNIT_PULSE_US : esc_output_t::UNIT_THROTTLE_INT16;
}

StartReport SimBackend::start(TimeUs) {
  for (std::size_t i = 0; i < size(); ++i) record(i, 0, true);
  return {};
}

std::int32_t SimBackend::to_hardware(std::size_t i, double u) const {
  return pulse_us_ ? pulse_from_normalized(u, escs_[i].pulse) : throttle_from_normalized(u);
}

double SimBackend::to_normalized(std::size_t i, std::int32_t hw) const {
  return pulse_us_ ? normalized_from_pulse(hw, escs_[i].pulse) : normalized_from_throttle(hw);
}

void SimBackend::write(const std::int32_t*, TimeUs) {}

}  // namespace tiller::esc
