// Live executor: runs nodes under LCM on wall-clock time (the only place in lib/ that reads a
// clock). Ticks follow each node's grid on CLOCK_REALTIME (us since the epoch, the time base
// lcm-logger stamps events with): a tick runs once the clock has reached its grid point and is
// told the grid time (node.hpp); ticks run are counted in "ticks.run" and grid points skipped
// after run() starts in "ticks.missed". Messages are delivered as they arrive, told their receive
// time. Receiving allocates nothing: channels are subscribed through LCM's C API, and the channel
// name reaches Node::deliver as a view.
//
// Every way out of run() calls every node's shutdown() (ESCs to neutral) first:
//   * SIGINT/SIGTERM (from construction on) or stop(): returns 0;
//   * an exception from a message handler: dropped, counted ("exception.message"), FAULT,
//     and the loop keeps running (a message never throws the process out of its loop);
//   * an exception from on_tick or an fd callback: counted ("exception.tick" /
//     "exception.fd"), FAULT; after kMaxConsecutiveFailures in a row from one node's tick (or
//     from fd callbacks) run() prints the reason and returns kExitFault (3);
//   * poll() failing other than EINTR: prints the reason and returns kExitFault.
//
// Message signing (auth/trailer.hpp, docs/safety.md "Who may command") is this transport's
// job, so node logic never sees it. With a key (auth::Policy), every message a node publishes
// leaves with a trailer naming that node as the sender; every received message is checked
// (auth/verifier.hpp) before any node sees it, and the trailer is stripped, so Node::deliver
// gets exactly the LCM message. A refused message is counted in each subscribing node's
// heartbeat as "rejected.auth.<verdict>" (unsigned, wrong_key, bad_mac, replay, window,
// streams_full), and a node's accept_only_from rule refuses other senders as
// "rejected.auth.sender"; the first refusal of each kind is also one line on stderr.
//
// Real time (runtime/realtime.hpp): when the process asked for it on its command line, add()
// gives every node the counters realtime.priority (the SCHED_FIFO priority in force, 0: none),
// realtime.locked (1: memory locked) and realtime.refused (1: part of the request was refused).
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <list>
#include <memory>
#include <string>
#include <vector>

#include "auth/verifier.hpp"
#include "runtime/node.hpp"

namespace lcm {
class LCM;
}  // namespace lcm
struct _lcm_recv_buf_t;
typedef struct _lcm_recv_buf_t lcm_recv_buf_t;

namespace tiller {

// Wall-clock time in us since the epoch (CLOCK_REALTIME).
TimeUs wall_time_us();

// Appends "ttl=0" to a udpm:// URL that does not say its TTL, so traffic stays on the host.
std::string with_default_ttl(const std::string& url);

class LiveExecutor {
 public:
  static constexpr int kExitFault = 3;
  static constexpr int kMaxConsecutiveFailures = 3;

  // Opens LCM at `url`; throws std::runtime_error with a clear message if it cannot.
  explicit LiveExecutor(const std::string& url) : LiveExecutor(url, auth::Policy{}) {}
  // With a signing policy (a key: sign and verify; require_signed: refuse unsigned input).
  // Throws std::runtime_error for require_signed without a key.
  LiveExecutor(const std::string& url, auth::Policy policy);
  ~LiveExecutor();

  void add(Node& node);
  // Calls `on_readable(now)` whenever `fd` is readable (a device, a pipe). Remove before close.
  void add_fd(int fd, std::function<void(TimeUs)> on_readable);
  void remove_fd(int fd);

  // Runs until SIGINT/SIGTERM or stop() (returns 0) or a fault (returns kExitFault); see above.
  int run();
  void stop();  // thread-safe: run() returns within 100 ms
  // Publishes raw bytes (for tools that are not nodes).
  // Publishes raw bytes (for tools that are not nodes), signed as the policy's raw_sender.
  void publish_raw(const std::string& channel, const void* data, int size);
  const auth::Policy& policy() const { return verifier_.policy(); }

 private:
  class LcmBus;
  struct Fd {
    int fd;
    std::function<void(TimeUs)> cb;
  };
  // Per node: its counters for refused messages (created in add(), so receiving allocates
  // nothing).
  struct NodeAuth {
    std::array<std::int64_t*, auth::kVerdicts> refused{};
    std::int64_t* sender = nullptr;
  };
  static void on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  void refuse(Node& n, std::size_t i, const auth::Checked& c, std::string_view channel, TimeUs now);
  void refuse_sender(Node& n, std::size_t i, const auth::Checked& c, std::string_view channel);
  int finish(int status);

  std::unique_ptr<lcm::LCM> lcm_;
  auth::Verifier verifier_;
  std::unique_ptr<LcmBus> raw_bus_;             // publish_raw
  std::vector<std::unique_ptr<LcmBus>> buses_;  // one per node: signs as that node
  std::vector<Node*> nodes_;
  std::vector<NodeAuth> node_auth_;
  std::array<bool, auth::kVerdicts + 1> told_{};  // first refusal of each kind printed
  std::vector<TimeUs> next_tick_;
  std::vector<int> tick_failures_;  // consecutive failed ticks per node
  std::vector<std::string> subscribed_;
  std::list<Fd> fds_;              // a list: callbacks may add or remove fds while one runs
  std::atomic<bool> stop_{false};  // stop() may come from another thread
};

}  // namespace tiller
