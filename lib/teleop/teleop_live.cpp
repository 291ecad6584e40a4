#include "teleop/teleop_live.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace tiller {

JoystickPump::JoystickPump(JsDevice& device, TeleopNode& node, LiveExecutor& ex,
                           TimeUs reopen_period)
    : dev_(device), node_(node), ex_(ex) {
  timer_fd_ = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (timer_fd_ < 0)
    throw std::runtime_error(std::string("timerfd_create: ") + std::strerror(errno));
  itimerspec its{};
  its.it_interval.tv_sec = reopen_period / kUsPerSecond;
  its.it_interval.tv_nsec = (reopen_period % kUsPerSecond) * 1000;
  its.it_value = its.it_interval;
  timerfd_settime(timer_fd_, 0, &its, nullptr);
  ex_.add_fd(timer_fd_, [this](TimeUs now) { on_timer(now); });
  on_timer(wall_time_us());
}

JoystickPump::~JoystickPump() {
  if (watched_fd_ >= 0) ex_.remove_fd(watched_fd_);
  ex_.remove_fd(timer_fd_);
  ::close(timer_fd_);
}

void JoystickPump::on_timer(TimeUs now) {
  std::uint64_t expirations = 0;
  while (::read(timer_fd_, &expirations, sizeof expirations) > 0) {
  }
  report_vehicle();
  if (!dev_.is_open()) {
    if (!dev_.try_open()) {
      if (dev_.last_error() != last_error_) {
        std::fprintf(stderr, "tiller-teleop: joystick absent: %s (retrying)\n",
                     dev_.last_error().c_str());
        last_error_ = dev_.last_error();
      }
      return;
    }
    watched_fd_ = dev_.poll_fd();
    ex_.add_fd(watched_fd_, [this](TimeUs t) { on_readable(t); });
  }
  handle(dev_.read(), now);  // a file's removal shows up here even without an inotify event
}

void JoystickPump::report_vehicle() {
  // The vehicle's word on arming (a refusal, a takeover), one line per change, for the pilot.
  const std::string& r = node_.vehicle_reason();
  if (r == reported_reason_ && node_.controller() == reported_controller_) return;
  reported_reason_ = r;
  reported_controller_ = node_.controller();
  std::fprintf(stderr, "tiller-teleop: vehicle %s%s%s: %s\n", node_.armed() ? "ARMED" : "disarmed",
               reported_controller_.empty() ? "" : ", in control: ", reported_controller_.c_str(),
               r.c_str());
}

void JoystickPump::on_readable(TimeUs now) {
  handle(dev_.read(), now);
}

void JoystickPump::handle(JsDevice::Status s, TimeUs now) {
  if (!dev_.is_open() && watched_fd_ >= 0) {
    ex_.remove_fd(watched_fd_);
    watched_fd_ = -1;
  }
  switch (s) {
    case JsDevice::Status::unchanged:
      return;
    case JsDevice::Status::connected:
      std::fprintf(stderr, "tiller-teleop: joystick connected: %s\n", dev_.description().c_str());
      last_error_.clear();
      break;
    case JsDevice::Status::disconnected:
      std::fprintf(stderr, "tiller-teleop: joystick lost: %s\n", dev_.last_error().c_str());
      last_error_ = dev_.last_error();
      break;
    case JsDevice::Status::changed:
      break;
    case JsDevice::Status::reinit:
      std::fprintf(stderr,
                   "tiller-teleop: %s sent start-up (INIT) events after ordinary input: neutral, "
                   "disarm requested, waiting for the stick to be centred (joystick.reinit)\n",
                   dev_.description().c_str());
      break;
  }
  if (node_.note_bad_js_events(dev_.parser().bad_events()) && !warned_bad_events_) {
    warned_bad_events_ = true;
    std::fprintf(stderr,
                 "tiller-teleop: dropping malformed js_event records from %s (unknown type or "
                 "number out of range; counted as rejected.js_event.bad)\n",
                 dev_.description().c_str());
  }
  node_.feed(dev_.state(), now);
  report_vehicle();
}

}  // namespace tiller
