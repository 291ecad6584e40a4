#include "runtime/live.hpp"

#include <lcm/lcm.h>
#include <poll.h>
#include <signal.h>
#include <time.h>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
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
    throw std::runtime_error("cannot open LCM at '" + u +
                             "' (no multicast route? try: ip route add 224.0.0.0/4 dev lo, see "
                             "docs/troubleshooting.md)");
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
  tick_failures_.push_back(0);
  for (const auto& ch : node.subscribed_channels()) {
    if (std::find(subscribed_.begin(), subscribed_.end(), ch) != subscribed_.end()) continue;
    subscribed_.push_back(ch);
    // The C API: lcm-cpp 1.3.1's callbacks turn the channel into a std::string per message
    // (a heap allocation for names over 15 characters, e.g. TILLER_THRUSTER_COMMAND).
    // LCM treats the name as a regular expression; Tiller's channel names are plain words.
    lcm_subscribe(lcm_->getUnderlyingLCM(), ch.c_str(), &LiveExecutor::on_message, this);
  }
}

void LiveExecutor::add_fd(int fd, std::function<void(TimeUs)> on_readable) {
  fds_.push_back(Fd{fd, std::move(on_readable)});
}

void LiveExecutor::remove_fd(int fd) {
  // Marked here, erased at the top of the next loop: a callback may remove its own fd.
  for (auto& f : fds_)
    if (f.fd == fd) f.fd = -1;
}

void LiveExecutor::on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  auto* self = static_cast<LiveExecutor*>(user);
  const TimeUs now = wall_time_us();
  const std::string_view ch(channel);
  // Node::deliver never throws: a handler's exception is caught, counted and latched there.
  for (Node* n : self->nodes_) n->deliver(ch, rbuf->data, static_cast<int>(rbuf->data_size), now);
}

void LiveExecutor::stop() {
  stop_.store(true);
}

void LiveExecutor::publish_raw(const std::string& channel, const void* data, int size) {
  lcm_->publish(channel, data, static_cast<unsigned>(size));
}

int LiveExecutor::finish(int status) {
  const TimeUs now = wall_time_us();
  for (Node* n : nodes_) {
    if (status != 0) n->publish_heartbeat_now(now);  // the last heartbeat says FAULT
    try {
      n->shutdown(now);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: shutdown() threw: %s\n", n->name().c_str(), e.what());
      status = kExitFault;
    } catch (...) {
      std::fprintf(stderr, "%s: shutdown() threw\n", n->name().c_str());
      status = kExitFault;
    }
  }
  return status;
}

int LiveExecutor::run() {
  std::vector<pollfd> pfds;
  std::vector<Fd*> owners;
  int fd_failures = 0;
  // The schedule starts now: time spent between add() and run() (opening devices, say) is not
  // counted as missed ticks.
  const TimeUs start = wall_time_us();
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    next_tick_[i] = std::max(next_tick_[i], nodes_[i]->next_tick_at_or_after(start));
  while (!stop_.load() && !g_signalled.load()) {
    TimeUs now = wall_time_us();
    // Tick every node that is due, told its grid time. A loop that fell behind runs only the
    // latest due grid point and counts the skipped ones.
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (next_tick_[i] > now) continue;
      Node& n = *nodes_[i];
      const TimeUs period = n.tick_period();
      const TimeUs behind = (now - next_tick_[i]) / period;
      n.count_missed_ticks(behind);
      const TimeUs t = next_tick_[i] + behind * period;
      next_tick_[i] = t + period;
      if (n.tick(t)) {
        tick_failures_[i] = 0;
      } else if (++tick_failures_[i] >= kMaxConsecutiveFailures) {
        std::fprintf(stderr, "%s: on_tick threw %d times in a row (%s); shutting down\n",
                     n.name().c_str(), tick_failures_[i], n.fault_status().c_str());
        return finish(kExitFault);
      }
    }
    TimeUs wake = std::numeric_limits<TimeUs>::max();
    for (TimeUs t : next_tick_) wake = std::min(wake, t);
    now = wall_time_us();
    int timeout_ms = 100;
    if (wake != std::numeric_limits<TimeUs>::max()) {
      timeout_ms = static_cast<int>(std::clamp<TimeUs>((wake - now + 999) / 1000, 0, 100));
    }
    fds_.remove_if([](const Fd& f) { return f.fd < 0; });
    pfds.clear();
    owners.clear();
    pfds.push_back(pollfd{lcm_->getFileno(), POLLIN, 0});
    for (auto& f : fds_) {
      pfds.push_back(pollfd{f.fd, POLLIN, 0});
      owners.push_back(&f);
    }
    const int r = poll(pfds.data(), pfds.size(), timeout_ms);
    if (r < 0) {
      if (errno == EINTR) continue;
      std::fprintf(stderr, "live executor: poll failed: %s; shutting down\n", std::strerror(errno));
      return finish(kExitFault);
    }
    if (r == 0) continue;
    if (pfds[0].revents & POLLIN) lcm_->handle();
    for (std::size_t i = 1; i < pfds.size(); ++i) {
      if (!(pfds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      Fd& f = *owners[i - 1];
      if (f.fd < 0) continue;  // removed by an earlier callback in this round
      try {
        f.cb(wall_time_us());
        fd_failures = 0;
      } catch (const std::exception& e) {
        for (Node* n : nodes_) n->record_fault("exception.fd", e.what());
        ++fd_failures;
      } catch (...) {
        for (Node* n : nodes_) n->record_fault("exception.fd", "unknown exception");
        ++fd_failures;
      }
      if (fd_failures >= kMaxConsecutiveFailures) {
        std::fprintf(stderr,
                     "live executor: an fd callback threw %d times in a row; shutting down\n",
                     fd_failures);
        return finish(kExitFault);
      }
    }
  }
  return finish(0);
}

}  // namespace tiller
