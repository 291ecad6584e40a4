// gpio::OutputLine on the Linux GPIO character device through libgpiod 1.6 (the v1 API of
// Debian bookworm's libgpiod-dev): gpiod_chip_open_lookup, gpiod_chip_get_line,
// gpiod_line_request_output(consumer, initial), gpiod_line_set_value. The consumer name shows in
// `gpioinfo`. When the process ends the kernel frees the line; the board's pull resistor then
// holds it (the Navigator pulls PWM_OE up: outputs off).
#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "gpio/output.hpp"

namespace tiller::gpio {
namespace {

class GpiodOutput : public OutputLine {
 public:
  GpiodOutput(gpiod_chip* chip, gpiod_line* line, int level, std::string name)
      : chip_(chip), line_(line), level_(level), name_(std::move(name)) {}
  ~GpiodOutput() override {
    gpiod_line_release(line_);
    gpiod_chip_close(chip_);
  }
  int set(int level) override {
    if (gpiod_line_set_value(line_, level) < 0) return errno;
    level_ = level;
    return 0;
  }
  int level() const override { return level_; }
  std::string name() const override { return name_; }

 private:
  gpiod_chip* chip_;
  gpiod_line* line_;
  int level_;
  std::string name_;
};

}  // namespace

std::unique_ptr<OutputLine> open_gpiod_output(const std::string& chip, unsigned offset, int initial,
                                              const std::string& consumer) {
  const std::string name = chip + ":" + std::to_string(offset);
  gpiod_chip* c = gpiod_chip_open_lookup(chip.c_str());
  if (c == nullptr) {
    throw std::runtime_error("cannot open GPIO chip " + chip + ": " + std::strerror(errno) +
                             " (`gpiodetect` lists the chips; the user needs the `gpio` group)");
  }
  gpiod_line* l = gpiod_chip_get_line(c, offset);
  if (l == nullptr || gpiod_line_request_output(l, consumer.c_str(), initial) < 0) {
    const int e = errno;
    gpiod_chip_close(c);
    throw std::runtime_error("cannot request GPIO line " + name + " as an output: " +
                             std::strerror(e) + " (`gpioinfo " + chip + "` shows who holds it)");
  }
  return std::make_unique<GpiodOutput>(c, l, initial, name);
}

}  // namespace tiller::gpio
