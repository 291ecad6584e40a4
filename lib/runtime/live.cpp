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
#include <optional>
#include <stdexcept>

#include "runtime/realtime.hpp"

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

// One per node (and one for publish_raw): with a key, signs every message as its sender.
class LiveExecutor::LcmBus : public Bus {
 public:
  LcmBus(lcm_t* l, const auth::Policy& policy, std::string_view sender) : lcm_(l) {
    if (policy.key) signer_.emplace(*policy.key, sender);
  }
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    channel_.assign(channel);  // reused: no allocation once long enough
    if (!signer_) {
      lcm_publish(lcm_, channel_.c_str(), data, static_cast<unsigned>(size));
      return;
    }
    const auto n = static_cast<std::size_t>(size) + auth::kTrailerSize;
    if (buf_.size() < n) buf_.resize(n);  // grows to the largest message once
    if (size > 0) std::memcpy(buf_.data(), data, static_cast<std::size_t>(size));
    signer_->sign(channel, data, size, wall_time_us(), buf_.data() + size);
    lcm_publish(lcm_, channel_.c_str(), buf_.data(), static_cast<unsigned>(n));
  }

 private:
  lcm_t* lcm_;
  std::optional<auth::Signer> signer_;
  std::string channel_;
  std::vector<std::uint8_t> buf_;
};

LiveExecutor::LiveExecutor(const std::string& url, auth::Policy policy)
    : verifier_(std::move(policy)) {
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
  raw_bus_ = std::make_unique<LcmBus>(lcm_->getUnderlyingLCM(), verifier_.policy(),
                                      verifier_.policy().raw_sender);
}

LiveExecutor::~LiveExecutor() {
  for (Node* n : nodes_) n->attach(nullptr);
}

void LiveExecutor::add(Node& node) {
  buses_.push_back(
      std::make_unique<LcmBus>(lcm_->getUnderlyingLCM(), verifier_.policy(), node.name()));
  node.attach(buses_.back().get());
  node.set_clock_offset(verifier_.policy().clock_offset_us);
  nodes_.push_back(&node);
  // The node's refusal counters, made now so that receiving allocates nothing.
  NodeAuth na;
  if (verifier_.policy().enabled()) {
    for (int v = 0; v < auth::kVerdicts; ++v) {
      const auto verdict = static_cast<auth::Verdict>(v);
      if (auth::accepted(verdict)) continue;
      na.refused[static_cast<std::size_t>(v)] =
          &node.executor_counter(std::string("rejected.auth.") + auth::to_string(verdict));
    }
  }
  if (verifier_.policy().key) {
    for (const auto& ch : node.subscribed_channels()) {
      if (node.allowed_senders(ch)) na.sender = &node.executor_counter("rejected.auth.sender");
    }
  }
  node_auth_.push_back(na);
  // Real time as the command line asked for it (runtime/realtime.hpp), in every heartbeat.
  if (const realtime::Report* rt = realtime::process_report()) {
    node.executor_counter("realtime.priority") = rt->priority;
    node.executor_counter("realtime.locked") = rt->locked ? 1 : 0;
    node.executor_counter("realtime.refused") = rt->granted() ? 0 : 1;
  }
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
  const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
  // Checked once for every node of the process, before any of them sees it (a stream's replay
  // state advances once per message); deliver() gets the message without its trailer.
  const auth::Checked c = self->verifier_.check(ch, data, static_cast<int>(rbuf->data_size), now);
  const bool keyed = self->verifier_.policy().key.has_value();
  for (std::size_t i = 0; i < self->nodes_.size(); ++i) {
    Node& n = *self->nodes_[i];
    if (!n.subscribes_to(ch)) continue;
    if (!auth::accepted(c.verdict)) {
      self->refuse(n, i, c, ch, now);
      continue;
    }
    if (keyed) {
      const auto* allowed = n.allowed_senders(ch);
      if (allowed && (c.verdict != auth::Verdict::kSigned ||
                      std::find(allowed->begin(), allowed->end(), c.sender) == allowed->end())) {
        self->refuse_sender(n, i, c, ch);
        continue;
      }
    }
    // Node::deliver never throws: a handler's exception is caught, counted and latched there.
    n.deliver(ch, data, c.payload_size, now);
  }
}

namespace {
const char* why(auth::Verdict v) {
  switch (v) {
    case auth::Verdict::kUnsigned:
      return "it is not signed, and require_signed is on";
    case auth::Verdict::kWrongKey:
      return "it is signed with another key than this process's";
    case auth::Verdict::kBadMac:
      return "its signature does not verify (altered or forged)";
    case auth::Verdict::kReplay:
      return "it is not newer than the last one accepted from its sender on this channel (a "
             "replay)";
    case auth::Verdict::kWindow:
      return "its time stamp is outside the window around this clock (an old capture, or the "
             "computers' clocks are not in step)";
    case auth::Verdict::kStreamsFull:
      return "too many (sender, channel) streams to track";
    default:
      return "?";
  }
}
}  // namespace

void LiveExecutor::refuse(Node& n, std::size_t i, const auth::Checked& c, std::string_view channel,
                          TimeUs now) {
  const auto v = static_cast<std::size_t>(c.verdict);
  if (std::int64_t* counter = node_auth_[i].refused[v]) n.count_transport_reject(*counter);
  if (told_[v]) return;
  told_[v] = true;
  std::fprintf(stderr, "%s: refused a message on %.*s: %s", n.name().c_str(),
               static_cast<int>(channel.size()), channel.data(), why(c.verdict));
  if (c.stamp != 0) {
    std::fprintf(stderr, " (stamp %+.3f s from this clock, window %.3f s)",
                 to_seconds(c.stamp - now), to_seconds(verifier_.policy().window_us));
  }
  std::fprintf(stderr, "; counted in rejected.auth.%s (said once)\n", auth::to_string(c.verdict));
}

void LiveExecutor::refuse_sender(Node& n, std::size_t i, const auth::Checked& c,
                                 std::string_view channel) {
  if (node_auth_[i].sender) n.count_transport_reject(*node_auth_[i].sender);
  if (told_[auth::kVerdicts]) return;
  told_[auth::kVerdicts] = true;
  const bool known = c.verdict == auth::Verdict::kSigned;
  std::fprintf(stderr,
               "%s: refused a message on %.*s from %s%.*s%s: this node accepts it only from its "
               "declared senders; counted in rejected.auth.sender (said once)\n",
               n.name().c_str(), static_cast<int>(channel.size()), channel.data(),
               known ? "'" : "an unsigned sender", static_cast<int>(c.sender.size()),
               c.sender.data(), known ? "'" : "");
}

void LiveExecutor::stop() {
  stop_.store(true);
}

void LiveExecutor::publish_raw(const std::string& channel, const void* data, int size) {
  raw_bus_->publish(channel, static_cast<const std::uint8_t*>(data), size);
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
