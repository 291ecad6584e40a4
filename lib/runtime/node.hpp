// The node: a process's logic as a class whose outputs depend only on the messages it was
// given and the time it was told (architecture.md, "one rule").
//
// A node declares, in its constructor, what it subscribes to (subscribe<Msg>(channel, handler))
// and what it publishes (advertise<Msg>(channel)), and a tick period. An executor delivers
// encoded messages with deliver(channel, bytes, now) and calls tick(t) on the node's tick grid.
// The node publishes through publish(); the executor decides where the bytes go (LCM, an
// in-process queue, a replay collector).
// Rules every executor follows, so that live, lockstep and replay runs agree:
//   * the time a tick is told is always a grid point t = k * period (k integer), in every
//     executor. The live executor runs a tick when the wall clock has reached its grid point
//     and tells it the grid time, not the wall time; when it falls behind by more than one
//     period it runs only the latest due grid point and counts the skipped ones in
//     "ticks.missed" (so the schedule of told times stays on the grid, and a late loop shows
//     in the heartbeat instead of as a burst of catch-up ticks);
//   * at one instant, due ticks run before messages stamped with that instant are delivered;
//   * a message is told its receive time (live), its queue instant (lockstep) or its recorded
//     time (replay).
// The base class decodes, counts malformed packets, and publishes a heartbeat on
// TILLER_HEARTBEAT_<NAME> at the first tick at or after each whole second of the node's time,
// with the counters (received, rejected, stale, published, and named per-reason counters).
// Error policy: handlers and on_tick must not throw; bad input is rejected with
// reject(counter). If one throws anyway, the base class catches it, counts it
// ("exception.message" / "exception.tick"), latches the heartbeat to STATE_FAULT and carries on;
// the live executor stops the process (every node's shutdown(), exit status 3) after repeated
// tick failures. Publishing on a channel that was not advertised still publishes but counts
// "unadvertised.<channel>".
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <tiller/count_guard.hpp>
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
  // Declared channels, sorted (the heartbeat channel is always among the published ones).
  std::vector<std::string> subscribed_channels() const;
  std::vector<std::string> published_channels() const;
  // LCM type name of a declared channel's messages ("" if the channel is not declared).
  std::string subscribed_type(std::string_view channel) const;
  std::string published_type(std::string_view channel) const;
  bool subscribes_to(std::string_view channel) const { return find_sub(channel) != nullptr; }
  // The senders this node accepts on `channel` (see accept_only_from), or nullptr when any
  // sender the transport accepts will do (also for a channel it does not subscribe to).
  const std::vector<std::string>* allowed_senders(std::string_view channel) const;
  bool advertises(std::string_view channel) const;
  // Decodes and dispatches one message. Never throws; a bad packet is counted. Looks the channel
  // up without building a string (no allocation).
  void deliver(std::string_view channel, const void* data, int size, TimeUs now);
  // Runs on_tick(now), then the heartbeat if one is due. Never throws: an exception from
  // on_tick is counted ("exception.tick") and latches FAULT; returns false if it threw.
  bool tick(TimeUs now);
  // Executor side, the live executor before each tick it runs: counts that tick in "ticks.run"
  // and the `n` grid points skipped before it in "ticks.missed".
  void count_missed_ticks(std::int64_t n);
  // Executor side: an exception outside the node's own handlers that concerns it (an fd
  // callback): counted under `counter_name` and latches FAULT with `what` as the status.
  void record_fault(const std::string& counter_name, const std::string& what);
  // True once any exception was caught for this node (its heartbeat says STATE_FAULT).
  bool faulted() const { return faulted_; }
  const std::string& fault_status() const { return fault_status_; }
  // Executor side: a named counter (created on first use; create it before the hot path) and a
  // message the transport refused for this node, counted there, in received and in rejected
  // (e.g. "rejected.auth.bad_mac": see runtime/live.hpp).
  std::int64_t& executor_counter(const std::string& name) { return counter(name); }
  void count_transport_reject(std::int64_t& reason) {
    ++received_;
    reject(reason);
  }
  // Executor side: publishes a heartbeat now, whether or not one is due (the live executor's
  // last word before it stops a faulted process).
  void publish_heartbeat_now(TimeUs now) { publish_heartbeat(now); }
  // First tick time at or after t on this node's grid.
  TimeUs next_tick_at_or_after(TimeUs t) const;
  // Called once by the live executor on SIGINT/SIGTERM before exit (e.g. ESCs to neutral).
  virtual void shutdown(TimeUs now) { (void)now; }
  // Executor side: the bound on the offset between this process's clock and its senders'
  // (core/time.hpp kDefaultClockOffsetUs unless the process was given another) that
  // on_time allows on a message's utime.
  void set_clock_offset(TimeUs us) { clock_offset_ = us; }
  TimeUs clock_offset() const { return clock_offset_; }

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

  // Declares that this node accepts messages on `channel` (already subscribed) only from these
  // senders: the names in the signed-message trailer (auth/trailer.hpp), i.e. the publishing
  // nodes' names. The live executor enforces it whenever the process has a signing key
  // (unsigned and other senders' messages are refused, counted in "rejected.auth.sender");
  // without a key there is no identity to check and the rule is reported, not enforced.
  // Example: tiller-esc accepts TILLER_THRUSTER_COMMAND only from "mixer".
  void accept_only_from(std::string_view channel, std::vector<std::string> senders);

  // Declares that this node publishes Msg on `channel` (call in the constructor).
  template <class Msg>
  void advertise(const std::string& channel) {
    advertise_type(channel, Msg::getTypeName());
  }

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
  // True when a message stamped `utime` by its sender's clock and received at `now` is on time
  // for an input whose freshness limit is `limit`: not older than limit + clock_offset() and not
  // more than clock_offset() ahead of `now` (core/time.hpp arrival_of). Else it counts the
  // message in "rejected.<input>.stale" or "rejected.<input>.future" (made on first use) and
  // returns false, and the handler drops the message before it changes anything:
  //   if (!on_time(odom_fresh_, m.utime, now, "odometry")) return;
  //   ... checks, copy ...
  //   odom_fresh_.mark(now, m.utime, clock_offset());
  bool on_time(TimeUs utime, TimeUs now, TimeUs limit, std::string_view input);
  bool on_time(const Freshness& f, TimeUs utime, TimeUs now, std::string_view input) {
    return on_time(utime, now, f.limit(), input);
  }
  // Counts an input going stale (see core/time.hpp Freshness).
  void count_stale(std::int64_t n = 1) { stale_ += n; }
  // State and one-line status reported in the heartbeat.
  void set_health(std::int8_t state, const std::string& status);

 private:
  struct SubscriptionBase {
    virtual ~SubscriptionBase() = default;
    virtual bool dispatch(const void* data, int size, TimeUs now) = 0;  // false: decode failed
    std::string channel;
    const char* type = "";
    std::int64_t* malformed = nullptr;
    std::vector<std::string> senders;  // empty: any sender
  };
  struct Advert {
    std::string channel;
    std::string type;
  };
  template <class Msg, class Derived>
  struct Subscription : SubscriptionBase {
    Derived* self;
    void (Derived::*handler)(const Msg&, TimeUs);
    Msg msg;
    bool dispatch(const void* data, int size, TimeUs now) override {
      // lcm-gen's decoders resize each array to the packet's count before checking that the
      // bytes are there: a short packet with a huge count would allocate gigabytes. The
      // generated guard (tools/lcm-count-guard.py) refuses it first, without allocating.
      if (!counts_fit<Msg>(data, size)) return false;
      // lcm-gen's decoders throw (std::length_error from a resize) on a negative array count:
      // that is a malformed packet like any other, not a fault of this node.
      int n = -1;
      try {
        n = msg.decode(data, 0, size);
      } catch (const std::exception&) {
        return false;
      }
      if (n != size) return false;
      (self->*handler)(msg, now);
      return true;
    }
  };

  SubscriptionBase* find_sub(std::string_view channel) const;
  void add_sub(const std::string& channel, const char* type, std::unique_ptr<SubscriptionBase> s);
  void advertise_type(const std::string& channel, const char* type);
  void publish_bytes(std::string_view channel, const std::uint8_t* data, int size);
  void publish_heartbeat(TimeUs now);
  void latch_fault(std::string_view what);

  std::string name_;
  TimeUs tick_period_;
  std::string heartbeat_channel_;
  Bus* bus_ = nullptr;
  // A node has a handful of channels: linear search over string_views beats hashing and needs
  // no temporary std::string.
  std::vector<std::unique_ptr<SubscriptionBase>> subs_;
  std::vector<Advert> adverts_;
  std::vector<std::pair<std::string, std::int64_t*>> unadvertised_;
  std::map<std::string, std::int64_t, std::less<>> counters_;
  TimeUs clock_offset_ = kDefaultClockOffsetUs;
  std::int64_t* exception_message_ = nullptr;
  std::int64_t* exception_tick_ = nullptr;
  std::int64_t* ticks_missed_ = nullptr;
  bool faulted_ = false;
  std::string fault_status_;
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
  add_sub(channel, Msg::getTypeName(), std::move(s));
}

template <class Msg>
void Node::publish(std::string_view channel, const Msg& msg) {
  const int n = msg.getEncodedSize();
  if (static_cast<int>(encode_buf_.size()) < n) encode_buf_.resize(static_cast<std::size_t>(n));
  if (msg.encode(encode_buf_.data(), 0, n) != n) return;
  publish_bytes(channel, encode_buf_.data(), n);
}

}  // namespace tiller
