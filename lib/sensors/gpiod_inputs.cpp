#include "sensors/gpiod_inputs.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

namespace tiller::sensors {

GpiodInputs::~GpiodInputs() {
  for (gpiod_line* l : lines_)
    if (l) gpiod_line_release(l);
  for (Chip& c : chips_) gpiod_chip_close(c.chip);
}

gpiod_chip* GpiodInputs::open_chip(const std::string& name, std::string& error) {
  for (Chip& c : chips_)
    if (c.name == name) return c.chip;
  gpiod_chip* chip = gpiod_chip_open_lookup(name.c_str());
  if (!chip) {
    const int e = errno;
    error = "cannot open GPIO chip " + name + ": " + std::strerror(e);
    if (e == ENOENT) error += " (`gpiodetect` lists the chips)";
    if (e == EACCES || e == EPERM)
      error += " (add the user to the group that owns /dev/gpiochip*, usually `gpio`)";
    return nullptr;
  }
  chips_.push_back({name, chip});
  return chip;
}

int GpiodInputs::request(const std::string& chip_name, unsigned offset, Bias bias,
                         const std::string& consumer, std::string& error) {
  gpiod_chip* chip = open_chip(chip_name, error);
  if (!chip) return -1;
  gpiod_line* line = gpiod_chip_get_line(chip, offset);
  if (!line) {
    error = chip_name + " has no line " + std::to_string(offset) + " (it has " +
            std::to_string(gpiod_chip_num_lines(chip)) + "): " + std::strerror(errno);
    return -1;
  }
  int flags = 0;
  if (bias == Bias::pull_up) flags = GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP;
  if (bias == Bias::pull_down) flags = GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN;
  if (bias == Bias::disable) flags = GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE;
  if (gpiod_line_request_input_flags(line, consumer.c_str(), flags) < 0) {
    const int e = errno;
    error = chip_name + " line " + std::to_string(offset) +
            ": cannot request it as an input: " + std::strerror(e);
    if (e == EBUSY) {
      const char* owner = gpiod_line_consumer(line);
      error += std::string(" (in use by ") + (owner ? owner : "another program") + ")";
    }
    return -1;
  }
  lines_.push_back(line);
  return static_cast<int>(lines_.size() - 1);
}

int GpiodInputs::read(int h) {
  if (h < 0 || h >= static_cast<int>(lines_.size()) || !lines_[h]) return -EINVAL;
  const int v = gpiod_line_get_value(lines_[h]);
  return v < 0 ? -errno : v;
}

void GpiodInputs::release(int h) {
  if (h < 0 || h >= static_cast<int>(lines_.size()) || !lines_[h]) return;
  gpiod_line_release(lines_[h]);
  lines_[h] = nullptr;
}

}  // namespace tiller::sensors
