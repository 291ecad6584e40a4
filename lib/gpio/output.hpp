// One digital output line (the PCA9685's output-enable pin on the Navigator), over a small
// interface so the ESC logic runs against a fake in tests (no /dev/gpiochip* on the build
// machine). The real line is gpio/gpiod_output.hpp (libgpiod 1.6, Debian bookworm's
// libgpiod-dev). Levels are physical (0 = low, 1 = high); what a level means (OE is active low:
// 0 = outputs on) is the caller's business. set() must not allocate.
#pragma once

#include <memory>
#include <string>

namespace tiller::gpio {

class OutputLine {
 public:
  virtual ~OutputLine() = default;
  // Drives the line: 0 or an errno.
  virtual int set(int level) = 0;
  // The level last driven (what the line is at), or -1 before the first successful set().
  virtual int level() const = 0;
  // "gpiochip0:26", for messages.
  virtual std::string name() const = 0;
};

// A fake line for tests: records the level and the number of changes; can be made to fail.
class FakeOutputLine : public OutputLine {
 public:
  explicit FakeOutputLine(int initial = 1, std::string name = "fake-gpio:0")
      : level_(initial), name_(std::move(name)) {}
  int set(int level) override {
    if (fail_with != 0) return fail_with;
    if (level != level_) ++changes;
    level_ = level;
    return 0;
  }
  int level() const override { return level_; }
  std::string name() const override { return name_; }
  int fail_with = 0;  // errno every set() returns (0: none)
  int changes = 0;

 private:
  int level_;
  std::string name_;
};

// Requests line `offset` of `chip` ("gpiochip0", "/dev/gpiochip0", a label or a number) as an
// output at `initial`, through libgpiod; throws std::runtime_error naming the chip, the line and
// the errno when it cannot (a missing output-enable line is a broken config, not a FAULT).
std::unique_ptr<OutputLine> open_gpiod_output(const std::string& chip, unsigned offset, int initial,
                                              const std::string& consumer);

}  // namespace tiller::gpio
