#include "sensors/dvl_link.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>

namespace tiller::sensors {

DvlLink::DvlLink(const DvlParams& p, DvlNode& node, LiveExecutor& ex)
    : node_(node),
      ex_(&ex),
      reconnect_s_(p.reconnect_s),
      client_(p.host, p.port, p.max_line, p.reconnect_s, p.connect_timeout_s) {
  timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (timer_fd_ >= 0) {
    const TimeUs period = from_seconds(std::min(p.reconnect_s, 0.25));
    itimerspec its{};
    its.it_value.tv_sec = period / kUsPerSecond;
    its.it_value.tv_nsec = (period % kUsPerSecond) * 1000;
    its.it_interval = its.it_value;
    ::timerfd_settime(timer_fd_, 0, &its, nullptr);
    ex_->add_fd(timer_fd_, [this](TimeUs now) { on_timer(now); });
  }
}

DvlLink::~DvlLink() {
  if (watched_ >= 0) ex_->remove_fd(watched_);
  if (timer_fd_ >= 0) {
    ex_->remove_fd(timer_fd_);
    ::close(timer_fd_);
  }
}

void DvlLink::service(TimeUs now) {
  client_.service(to_seconds(now));
  after(now);
}

void DvlLink::on_timer(TimeUs now) {
  std::uint64_t n = 0;
  while (::read(timer_fd_, &n, sizeof n) > 0) {
  }
  service(now);
}

void DvlLink::on_readable(TimeUs now) {
  client_.read_available(to_seconds(now), [&](std::string_view line) { node_.feed(line, now); });
  after(now);
}

void DvlLink::after(TimeUs now) {
  const int fd = client_.fd();
  if (fd != watched_) {
    if (watched_ >= 0) ex_->remove_fd(watched_);
    watched_ = fd;
    if (fd >= 0) ex_->add_fd(fd, [this](TimeUs t) { on_readable(t); });
  }
  const bool up = client_.connected();
  if (up && !up_) {
    std::fprintf(stderr, "tiller-dvl: connected to the DVL at %s:%d\n", client_.host().c_str(),
                 client_.port());
    said_.clear();
    node_.set_link(true, "", now);
  } else if (!up && client_.state() == TcpLineClient::State::kDown) {
    const std::string& why = client_.last_error();
    if (up_ || why != said_) {
      if (why != said_)
        std::fprintf(stderr, "tiller-dvl: not connected to %s:%d: %s; retrying every %g s\n",
                     client_.host().c_str(), client_.port(), why.c_str(), reconnect_s_);
      said_ = why;
      node_.set_link(false, why, now);
    }
  }
  up_ = up;
  node_.count_link(client_.connects(), client_.disconnects(), client_.overlong());
}

}  // namespace tiller::sensors
