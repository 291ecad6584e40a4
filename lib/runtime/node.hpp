// The node: a process's logic as a class whose outputs depend only on the messages it was
// given and the time it was told (architecture.md, "one rule").
//
// A node declares its subscriptions (typed LCM messages) and a tick period. An executor
// delivers encoded messages with deliver(channel, bytes, now) and calls tick(now) on the
// node's tick grid (every multiple of the period). The node publishes through publish(); the
// executor decides where the bytes go (LCM, an in-process queue, a replay collector).
// Rules every executor follows, so that live, lockstep and replay runs agree:
//   * ticks happen at times t = k * period (k integer);
//   * at one instant, due ticks run before messages stamped with that instant are delivered.
// The base class decodes, counts malformed packets, and publishes a heartbeat at 1 Hz on
// TILLER_HEARTBEAT_<NAME> with the counters (received, rejected, stale, published, and named
// per-reason counters). Handlers must not throw; bad input is rejected with reject(counter).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <tiller/heartbeat_t.hpp>

#include "core/time.hpp"

namespace tiller {

// Where a node's encoded outputs go. Each executor provides one.
class Bus {
 public:
  virtual ~Bus() = default;
  virtual void publish(std::string_view channel, const std::uint8_t* data, int size) = 0;
};

class Node {
 public:
  Node(std::string name, TimeUs tick_period_us);
  virtual ~Node();
  Node(const Node&) = delete;
  Node& operator=(const Node&) = delete;

  const std::string& name() const { return name_; }
  TimeUs tick_period() const { return tick_period_; }
  const std::string& heartbeat_channel() const { return heartbeat_channel_; }

  // ---- executor side
  void attach(Bus* bus) { bus_ = bus; }
  std::vector<std::string> subscribed_channels() const;
  bool subscribes_to(const std::string& channel) const { return subs_.count(channel) != 0; }
  // Decodes and dispatches one message. Never throws; a bad packet is counted.
  void deliver(const std::string& channel, const void* data, int size, TimeUs now);
  // Runs on_tick(now), then the heartbeat if one is due.
  void tick(TimeUs now);
  // First tick time at or after t on this node's grid.
  TimeUs next_tick_at_or_after(TimeUs t) const;
  // Called once by the live executor on SIGINT/SIGTERM before exit (e.g. ESCs to neutral).
  virtual void shutdown(TimeUs now) { (void)now; }

  // ---- counters (for tests and heartbeats)
  std::int64_t received() const { return received_; }
  std::int64_t rejected() const { return rejected_; }
  std::int64_t stale() const { return stale_; }
  std::int64_t published() const { return published_; }
  // Named counter value, 0 if it does not exist.
  std::int64_t counter_value(const std::string& name) const;

 protected:
  virtual void on_tick(TimeUs now) = 0;

  // Subscribes `handler` to `channel`; messages arrive decoded (the decode target is reused,
  // so steady-state delivery does not allocate).
  template <class Msg, class Derived>
  void subscribe(const std::string& channel, void (Derived::*handler)(const Msg&, TimeUs));

  // Encodes and publishes a message (the encode buffer is reused; no allocation).
  template <class Msg>
  void publish(std::string_view channel, const Msg& msg);

  // A named counter, created on first use (do it in the constructor); the reference stays valid.
  std::int64_t& counter(const std::string& name);
  // Counts a dropped message under `reason` and in the total; returns false for `return
  // reject(..)`.
  bool reject(std::int64_t& reason) {
    ++reason;
    ++rejected_;
    return false;
  }
  // Counts an input going stale (see core/time.hpp Freshness).
  void count_stale(std::int64_t n = 1) { stale_ += n; }
  // State and one-line status reported in the heartbeat.
  void set_health(std::int8_t state, const std::string& status);

 private:
  struct SubscriptionBase {
    virtual ~SubscriptionBase() = default;
    virtual bool dispatch(const void* data, int size, TimeUs now) = 0;  // false: decode failed
    std::int64_t* malformed = nullptr;
  };
  template <class Msg, class Derived>
  struct Subscription : SubscriptionBase {
    Derived* self;
    void (Derived::*handler)(const Msg&, TimeUs);
    Msg msg;
    bool dispatch(const void* data, int size, TimeUs now) override {
      if (msg.decode(data, 0, size) != size) return false;
      (self->*handler)(msg, now);
      return true;
    }
  };

  void publish_bytes(std::string_view channel, const std::uint8_t* data, int size);
  void publish_heartbeat(TimeUs now);

  std::string name_;
  TimeUs tick_period_;
  std::string heartbeat_channel_;
  Bus* bus_ = nullptr;
  std::unordered_map<std::string, std::unique_ptr<SubscriptionBase>> subs_;
  std::map<std::string, std::int64_t> counters_;
  std::vector<std::uint8_t> encode_buf_;
  std::int64_t received_ = 0, rejected_ = 0, stale_ = 0, published_ = 0;
  TimeUs next_heartbeat_ = INT64_MIN;
  heartbeat_t heartbeat_;
};

template <class Msg, class Derived>
void Node::subscribe(const std::string& channel, void (Derived::*handler)(const Msg&, TimeUs)) {
  auto s = std::make_unique<Subscription<Msg, Derived>>();
  s->self = static_cast<Derived*>(this);
  s->handler = handler;
  s->malformed = &counter("malformed." + channel);
  subs_[channel] = std::move(s);
}

template <class Msg>
void Node::publish(std::string_view channel, const Msg& msg) {
  const int n = msg.getEncodedSize();
  if (static_cast<int>(encode_buf_.size()) < n) encode_buf_.resize(static_cast<std::size_t>(n));
  if (msg.encode(encode_buf_.data(), 0, n) != n) return;
  publish_bytes(channel, encode_buf_.data(), n);
}

}  // namespace tiller
