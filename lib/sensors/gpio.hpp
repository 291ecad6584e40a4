// Digital inputs for the leak probes: a small interface over the Linux GPIO character device,
// so that the leak logic runs against a fake in tests (no /dev/gpiochip* on the build machine).
//
// GpioInputs hands out input lines by (chip, offset) and reads their physical level; the
// active level (active-high or active-low probe) is the caller's business, so the fake and the
// real lines behave alike. The real implementation is sensors/gpiod_inputs.hpp (libgpiod 1.6,
// Debian bookworm's libgpiod-dev: gpiod_chip_open_lookup, gpiod_chip_get_line,
// gpiod_line_request_input_flags, gpiod_line_get_value). read() must not allocate.
#pragma once

#include <string>

namespace tiller::sensors {

enum class Bias { as_is, pull_up, pull_down, disable };

class GpioInputs {
 public:
  virtual ~GpioInputs() = default;
  // Requests line `offset` of `chip` ("gpiochip0", "/dev/gpiochip0", a chip label, or a
  // number) as an input with this bias. Returns a handle >= 0, or -1 with `error` saying why
  // (the chip, the line and the errno).
  virtual int request(const std::string& chip, unsigned offset, Bias bias,
                      const std::string& consumer, std::string& error) = 0;
  // The physical level of a requested line: 0 or 1, or -errno when it cannot be read.
  virtual int read(int handle) = 0;
  // Gives a line back (after a read error, before asking for it again).
  virtual void release(int handle) = 0;
};

// A fake for tests and benchmarks: lines spring into being on request unless marked missing;
// the test sets their levels and read errors.
class FakeGpio : public GpioInputs {
 public:
  struct Line {
    std::string chip;
    unsigned offset = 0;
    Bias bias = Bias::as_is;
    int level = 0;
    int read_error = 0;  // errno a read returns (0: none)
    bool requested = false;
  };
  int request(const std::string& chip, unsigned offset, Bias bias, const std::string& consumer,
              std::string& error) override;
  int read(int handle) override;
  void release(int handle) override;

  // The line (chip, offset), created if needed.
  Line& line(const std::string& chip, unsigned offset);
  bool missing_chip = false;  // every request fails with ENOENT
  int requests = 0;

 private:
  Line lines_[32];
  int n_ = 0;
};

}  // namespace tiller::sensors
