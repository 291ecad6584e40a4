// GpioInputs on the Linux GPIO character device through libgpiod 1.6 (Debian bookworm's
// libgpiod-dev, the v1 API): gpiod_chip_open_lookup(chip), gpiod_chip_get_line(offset),
// gpiod_line_request_input_flags(consumer, bias flag), gpiod_line_get_value. The consumer
// name shows in `gpioinfo`. Needs read/write access to /dev/gpiochipN (group gpio on a
// Raspberry Pi, or root). This code cannot run on the build machine; tests use FakeGpio.
#pragma once

#include <string>
#include <vector>

#include "sensors/gpio.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace tiller::sensors {

class GpiodInputs : public GpioInputs {
 public:
  GpiodInputs() = default;
  ~GpiodInputs() override;
  GpiodInputs(const GpiodInputs&) = delete;
  GpiodInputs& operator=(const GpiodInputs&) = delete;

  int request(const std::string& chip, unsigned offset, Bias bias, const std::string& consumer,
              std::string& error) override;
  int read(int handle) override;
  void release(int handle) override;

 private:
  gpiod_chip* open_chip(const std::string& name, std::string& error);
  struct Chip {
    std::string name;
    gpiod_chip* chip = nullptr;
  };
  std::vector<Chip> chips_;
  std::vector<gpiod_line*> lines_;
};

}  // namespace tiller::sensors
