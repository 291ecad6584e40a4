// Live executor: runs nodes under LCM on wall-clock time (the only place in lib/ that reads a
// clock). Ticks follow each node's grid on CLOCK_REALTIME (us since the epoch, the time base
// lcm-logger stamps events with); messages are delivered as they arrive with the receive time.
// SIGINT/SIGTERM (from construction on) end run() cleanly: every node's shutdown() runs
// (ESCs to neutral) first.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "runtime/node.hpp"

namespace lcm {
class LCM;
class ReceiveBuffer;
}  // namespace lcm

namespace tiller {

// Wall-clock time in us since the epoch (CLOCK_REALTIME).
TimeUs wall_time_us();

// Appends "ttl=0" to a udpm:// URL that does not say its TTL, so traffic stays on the host.
std::string with_default_ttl(const std::string& url);

class LiveExecutor {
 public:
  // Opens LCM at `url`; throws std::runtime_error with a clear message if it cannot.
  explicit LiveExecutor(const std::string& url);
  ~LiveExecutor();

  void add(Node& node);
  // Calls `on_readable(now)` whenever `fd` is readable (a device, a pipe). Remove before close.
  void add_fd(int fd, std::function<void(TimeUs)> on_readable);
  void remove_fd(int fd);

  // Runs until SIGINT/SIGTERM or stop(); returns 0.
  int run();
  void stop();
  // Publishes raw bytes (for tools that are not nodes).
  void publish_raw(const std::string& channel, const void* data, int size);

 private:
  class LcmBus;
  struct Fd {
    int fd;
    std::function<void(TimeUs)> cb;
  };
  static void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel,
                         LiveExecutor* self);

  std::unique_ptr<lcm::LCM> lcm_;
  std::unique_ptr<LcmBus> bus_;
  std::vector<Node*> nodes_;
  std::vector<TimeUs> next_tick_;
  std::vector<std::string> subscribed_;
  std::vector<Fd> fds_;
  bool stop_ = false;
};

}  // namespace tiller
