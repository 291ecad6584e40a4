#include "runtime/live.hpp"

#include <poll.h>
#include <signal.h>
#include <time.h>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <limits>
#include <stdexcept>

namespace tiller {

namespace {
std::atomic<bool> g_signalled{false};
extern "C" void on_signal(int) {
  g_signalled.store(true);
}
}  // namespace

TimeUs wall_time_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<TimeUs>(ts.tv_sec) * kUsPerSecond + ts.tv_nsec / 1000;
}

std::string with_default_ttl(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0 || url.find("ttl=") != std::string::npos) return url;
  return url + (url.find('?') == std::string::npos ? "?ttl=0" : "&ttl=0");
}

class LiveExecutor::LcmBus : public Bus {
 public:
  explicit LcmBus(lcm::LCM& l) : lcm_(l) {}
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    channel_.assign(channel);  // reused: no allocation once long enough
    lcm_.publish(channel_, data, static_cast<unsigned>(size));
  }

 private:
  lcm::LCM& lcm_;
  std::string channel_;
};

LiveExecutor::LiveExecutor(const std::string& url) {
  // Handlers go in first: a SIGINT/SIGTERM that arrives while the program is still starting is
  // remembered, and run() then returns at once after every node's shutdown() (ESCs to neutral).
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  const std::string u = with_default_ttl(url);
  lcm_ = std::make_unique<lcm::LCM>(u);
  if (!lcm_->good()) {
    throw std::runtime_error(
        "cannot open LCM at '" + u +
        "' (no multicast route? try: ip route add 224.0.0.0/4 dev lo, see README)");
  }
  bus_ = std::make_unique<LcmBus>(*lcm_);
}

LiveExecutor::~LiveExecutor() {
  for (Node* n : nodes_) n->attach(nullptr);
}

void LiveExecutor::add(Node& node) {
  node.attach(bus_.get());
  nodes_.push_back(&node);
  next_tick_.push_back(node.next_tick_at_or_after(wall_time_us()));
  for (const auto& ch : node.subscribed_channels()) {
    if (std::find(subscribed_.begin(), subscribed_.end(), ch) != subscribed_.end()) continue;
    subscribed_.push_back(ch);
    lcm_->subscribeFunction(ch, &LiveExecutor::on_message, this);
  }
}

void LiveExecutor::add_fd(int fd, std::function<void(TimeUs)> on_readable) {
  fds_.push_back(Fd{fd, std::move(on_readable)});
}

void LiveExecutor::remove_fd(int fd) {
  fds_.erase(std::remove_if(fds_.begin(), fds_.end(), [fd](const Fd& f) { return f.fd == fd; }),
             fds_.end());
}

void LiveExecutor::on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                              LiveExecutor* self) {
  const TimeUs now = wall_time_us();
  for (Node* n : self->nodes_) {
    if (n->subscribes_to(channel))
      n->deliver(channel, rbuf->data, static_cast<int>(rbuf->data_size), now);
  }
}

void LiveExecutor::stop() {
  stop_ = true;
}

void LiveExecutor::publish_raw(const std::string& channel, const void* data, int size) {
  lcm_->publish(channel, data, static_cast<unsigned>(size));
}

int LiveExecutor::run() {
  std::vector<pollfd> pfds;
  while (!stop_ && !g_signalled.load()) {
    TimeUs now = wall_time_us();
    // Tick every node that is due (a late loop catches up by skipping to the next grid point).
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (next_tick_[i] <= now) {
        nodes_[i]->tick(now);
        next_tick_[i] = nodes_[i]->next_tick_at_or_after(now + 1);
      }
    }
    TimeUs wake = std::numeric_limits<TimeUs>::max();
    for (TimeUs t : next_tick_) wake = std::min(wake, t);
    now = wall_time_us();
    int timeout_ms = 100;
    if (wake != std::numeric_limits<TimeUs>::max()) {
      timeout_ms = static_cast<int>(std::clamp<TimeUs>((wake - now + 999) / 1000, 0, 100));
    }
    pfds.clear();
    pfds.push_back(pollfd{lcm_->getFileno(), POLLIN, 0});
    for (const auto& f : fds_) pfds.push_back(pollfd{f.fd, POLLIN, 0});
    const int r = poll(pfds.data(), pfds.size(), timeout_ms);
    if (r < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (r == 0) continue;
    if (pfds[0].revents & POLLIN) lcm_->handle();
    for (std::size_t i = 1; i < pfds.size(); ++i) {
      if (pfds[i].revents & (POLLIN | POLLHUP | POLLERR)) {
        const int fd = pfds[i].fd;
        auto it = std::find_if(fds_.begin(), fds_.end(), [fd](const Fd& f) { return f.fd == fd; });
        if (it != fds_.end()) {
          auto cb = it->cb;  // the callback may remove its own fd
          cb(wall_time_us());
        }
      }
    }
  }
  const TimeUs now = wall_time_us();
  for (Node* n : nodes_) n->shutdown(now);
  return 0;
}

}  // namespace tiller
