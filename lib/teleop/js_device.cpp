#include "teleop/js_device.hpp"

#include <fcntl.h>
#include <linux/joystick.h>
#include <sys/inotify.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace tiller {

static_assert(sizeof(js_event) == sizeof(JsEvent), "matches the kernel's struct js_event");
static_assert(JS_EVENT_BUTTON == kJsEventButton && JS_EVENT_AXIS == kJsEventAxis &&
              JS_EVENT_INIT == kJsEventInit);

int JsEventParser::feed(const std::uint8_t* data, std::size_t n, joystick_state_t& state) {
  int applied = 0;
  while (n > 0) {
    const std::size_t take = std::min(n, sizeof(JsEvent) - pending_);
    std::memcpy(buf_ + pending_, data, take);
    pending_ += take;
    data += take;
    n -= take;
    if (pending_ == sizeof(JsEvent)) {
      JsEvent e;
      std::memcpy(&e, buf_, sizeof e);
      pending_ = 0;
      apply(e, state);
      ++applied;
    }
  }
  return applied;
}

void JsEventParser::apply(const JsEvent& e, joystick_state_t& s) {
  if (e.type & kJsEventInit) {
    ++init_events_;
    if (ordinary_seen_ && ++late_init_events_ <= INT32_MAX) ++s.late_inits;
  } else {
    ordinary_seen_ = true;
  }
  const std::uint8_t type = e.type & static_cast<std::uint8_t>(~kJsEventInit);
  if (type == kJsEventAxis && e.number < kJsMaxAxes) {
    if (s.n_axes <= e.number) {
      s.n_axes = e.number + 1;
      s.axes.resize(static_cast<std::size_t>(s.n_axes), 0);
    }
    s.axes[e.number] = e.value;
  } else if (type == kJsEventButton && e.number < kJsMaxButtons) {
    if (s.n_buttons <= e.number) {
      s.n_buttons = e.number + 1;
      s.buttons.resize(static_cast<std::size_t>(s.n_buttons), false);
    }
    s.buttons[e.number] = e.value != 0;
  } else {
    ++bad_events_;
  }
}

JsDevice::JsDevice(std::string path, std::string name)
    : path_(std::move(path)), name_(std::move(name)) {
  state_.utime = 0;
  state_.device = path_.empty() ? name_ : path_;
  state_.connected = false;
  state_.n_axes = 0;
  state_.n_buttons = 0;
  state_.late_inits = 0;
  description_ = state_.device;
}

JsDevice::~JsDevice() {
  close_device();
}

void JsDevice::close_device() {
  if (inotify_fd_ >= 0) ::close(inotify_fd_);
  if (fd_ >= 0) ::close(fd_);
  inotify_fd_ = fd_ = -1;
  parser_.reset();
}

int JsDevice::poll_fd() const {
  return regular_file_ && inotify_fd_ >= 0 ? inotify_fd_ : fd_;
}

bool JsDevice::try_open() {
  if (fd_ >= 0) return true;
  std::string path = path_;
  int fd = -1;
  if (path.empty()) {
    for (int i = 0; i < 32 && fd < 0; ++i) {
      const std::string p = "/dev/input/js" + std::to_string(i);
      const int f = ::open(p.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
      if (f < 0) continue;
      char nm[128] = {};
      if (ioctl(f, JSIOCGNAME(sizeof nm - 1), nm) >= 0 && std::strstr(nm, name_.c_str())) {
        fd = f;
        path = p;
      } else {
        ::close(f);
      }
    }
    if (fd < 0) {
      error_ = "no /dev/input/js* device named like '" + name_ + "'";
      return false;
    }
  } else {
    fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      error_ = path + ": " + std::strerror(errno);
      return false;
    }
  }
  struct stat st {};
  fstat(fd, &st);
  regular_file_ = S_ISREG(st.st_mode);
  is_fifo_ = S_ISFIFO(st.st_mode);
  fd_ = fd;
  open_path_ = path;
  description_ = path;
  state_.n_axes = 0;
  state_.n_buttons = 0;
  if (S_ISCHR(st.st_mode)) {
    unsigned char na = 0, nb = 0;
    char nm[128] = {};
    // The counts go into the description only: an axis counts once the driver has reported it
    // (its INIT event), so an axis whose start-up state has not been read yet is absent, not 0.
    if (ioctl(fd, JSIOCGAXES, &na) < 0) na = 0;
    if (ioctl(fd, JSIOCGBUTTONS, &nb) < 0) nb = 0;
    if (ioctl(fd, JSIOCGNAME(sizeof nm - 1), nm) >= 0) description_ = path + " (" + nm + ")";
    description_ += " [" + std::to_string(na) + " axes, " + std::to_string(nb) + " buttons]";
  }
  state_.axes.assign(static_cast<std::size_t>(state_.n_axes), 0);
  state_.buttons.assign(static_cast<std::size_t>(state_.n_buttons), false);
  if (regular_file_) {
    inotify_fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (inotify_fd_ < 0 ||
        inotify_add_watch(inotify_fd_, path.c_str(),
                          IN_MODIFY | IN_ATTRIB | IN_DELETE_SELF | IN_MOVE_SELF) < 0) {
      error_ = path + ": inotify: " + std::strerror(errno);
      close_device();
      return false;
    }
  }
  if (is_fifo_) {
    // A FIFO with no writer reads EOF at once (and polls as hung up): treat it as absent.
    std::uint8_t buf[256];
    const ssize_t r = ::read(fd_, buf, sizeof buf);
    if (r == 0 || (r < 0 && errno != EAGAIN && errno != EINTR)) {
      error_ = path + ": FIFO has no writer";
      close_device();
      return false;
    }
    if (r > 0) {
      parser_.feed(buf, static_cast<std::size_t>(r), state_);
      state_.connected = true;
      announce_ = true;
    }
  }
  return true;
}

JsDevice::Status JsDevice::disconnect(const std::string& why) {
  close_device();
  error_ = why;
  const bool was = state_.connected;
  state_.connected = false;
  std::fill(state_.axes.begin(), state_.axes.end(), 0);
  std::fill(state_.buttons.begin(), state_.buttons.end(), false);
  announce_ = false;
  return was ? Status::disconnected : Status::unchanged;
}

JsDevice::Status JsDevice::read() {
  if (fd_ < 0) return Status::unchanged;
  if (regular_file_) {
    std::uint8_t ev[1024];
    while (::read(inotify_fd_, ev, sizeof ev) > 0) {
    }
    struct stat st {};
    if (fstat(fd_, &st) < 0 || st.st_nlink == 0) return disconnect(open_path_ + ": file removed");
  }
  bool any = false;
  const std::int32_t late_before = state_.late_inits;
  std::uint8_t buf[64 * sizeof(JsEvent)];
  for (;;) {
    const ssize_t r = ::read(fd_, buf, sizeof buf);
    if (r > 0) {
      parser_.feed(buf, static_cast<std::size_t>(r), state_);
      any = true;
      continue;
    }
    if (r == 0) {
      if (regular_file_) break;  // end of the file so far: wait for more
      return disconnect(open_path_ + ": end of stream (writer closed)");
    }
    if (errno == EINTR) continue;
    if (errno == EAGAIN) break;
    return disconnect(open_path_ + ": " + std::strerror(errno));  // ENODEV: unplugged
  }
  if (announce_) {
    announce_ = false;
    return Status::connected;
  }
  if (!any) return Status::unchanged;
  if (!state_.connected) {
    state_.connected = true;
    return Status::connected;
  }
  return state_.late_inits != late_before ? Status::reinit : Status::changed;
}

}  // namespace tiller
