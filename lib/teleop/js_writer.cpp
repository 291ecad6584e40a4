#include "teleop/js_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "teleop/js_device.hpp"

namespace tiller {

JsFifoWriter::JsFifoWriter(std::string path) : path_(std::move(path)) {
  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0) {
    if (!S_ISFIFO(st.st_mode)) throw std::runtime_error(path_ + ": exists and is not a FIFO");
  } else if (::mkfifo(path_.c_str(), 0600) != 0 && errno != EEXIST) {
    throw std::runtime_error(path_ + ": cannot make the FIFO: " + std::strerror(errno));
  }
}

JsFifoWriter::~JsFifoWriter() {
  close();
}

bool JsFifoWriter::open_for_writing() {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);  // blocks until the reader opens
  first_ = true;
  return fd_ >= 0;
}

bool JsFifoWriter::write(const joystick_state_t& s, std::uint32_t time_ms) {
  if (fd_ < 0) return false;
  JsEvent events[kJsMaxAxes + kJsMaxButtons];
  int n = 0;
  const int na = std::min<int>(s.n_axes, kJsMaxAxes),
            nb = std::min<int>(s.n_buttons, kJsMaxButtons);
  axes_.resize(static_cast<std::size_t>(na), 0);
  buttons_.resize(static_cast<std::size_t>(nb), false);
  const std::uint8_t init = first_ ? kJsEventInit : 0;
  for (int i = 0; i < na; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (first_ || s.axes[k] != axes_[k])
      events[n++] = {time_ms, s.axes[k], static_cast<std::uint8_t>(kJsEventAxis | init),
                     static_cast<std::uint8_t>(i)};
    axes_[k] = s.axes[k];
  }
  for (int i = 0; i < nb; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (first_ || s.buttons[k] != buttons_[k])
      events[n++] = {time_ms, static_cast<std::int16_t>(s.buttons[k] ? 1 : 0),
                     static_cast<std::uint8_t>(kJsEventButton | init),
                     static_cast<std::uint8_t>(i)};
    buttons_[k] = s.buttons[k];
  }
  first_ = false;
  const auto bytes = static_cast<std::size_t>(n) * sizeof(JsEvent);
  // One write of at most 192 * 8 bytes: below PIPE_BUF (4096), so it is atomic.
  return bytes == 0 || ::write(fd_, events, bytes) == static_cast<ssize_t>(bytes);
}

void JsFifoWriter::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace tiller
