#include "sensors/gpio.hpp"

#include <cerrno>
#include <stdexcept>

namespace tiller::sensors {

FakeGpio::Line& FakeGpio::line(const std::string& chip, unsigned offset) {
  for (int i = 0; i < n_; ++i)
    if (lines_[i].chip == chip && lines_[i].offset == offset) return lines_[i];
  if (n_ == 32) throw std::length_error("FakeGpio: more than 32 lines");
  lines_[n_].chip = chip;
  lines_[n_].offset = offset;
  return lines_[n_++];
}

int FakeGpio::request(const std::string& chip, unsigned offset, Bias bias, const std::string&,
                      std::string& error) {
  ++requests;
  if (missing_chip) {
    error = "cannot open GPIO chip " + chip + ": No such file or directory";
    return -1;
  }
  Line& l = line(chip, offset);
  if (l.requested) {
    error = chip + " line " + std::to_string(offset) + ": Device or resource busy";
    return -1;
  }
  l.requested = true;
  l.bias = bias;
  return static_cast<int>(&l - lines_);
}

int FakeGpio::read(int h) {
  if (h < 0 || h >= n_ || !lines_[h].requested) return -EINVAL;
  if (lines_[h].read_error != 0) return -lines_[h].read_error;
  return lines_[h].level ? 1 : 0;
}

void FakeGpio::release(int h) {
  if (h >= 0 && h < n_) lines_[h].requested = false;
}

}  // namespace tiller::sensors
