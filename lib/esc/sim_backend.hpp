// The sim backend: no bus. Every ESC is present, writes always succeed, and what would be on
// the bus goes out only in esc_output_t (TILLER_ESC_OUTPUT), which tiller-sim turns into
// thrust. The hardware unit is chosen in config: int16 throttle (like the I2C ESCs) or pulse
// width in us (like PWM ESCs, with each ESC's min/neutral/max).
#pragma once

#include "esc/backend.hpp"

namespace tiller::esc {

class SimBackend : public EscBackend {
 public:
  SimBackend(std::vector<EscChannelParams> escs, bool pulse_us);
  std::int8_t unit() const override;
  std::string bus() const override { return "sim"; }
  StartReport start(TimeUs now) override;
  std::int32_t to_hardware(std::size_t i, double u) const override;
  double to_normalized(std::size_t i, std::int32_t hw) const override;
  void write(const std::int32_t* hw, TimeUs now) override;

 private:
  bool pulse_us_;
};

}  // namespace tiller::esc
