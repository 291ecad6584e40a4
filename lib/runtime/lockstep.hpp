// In-process lockstep executor: many nodes in one process on simulated time.
//
// Time jumps from one due tick to the next; nothing waits on a clock, so a ten-minute mission
// runs in well under a second. Order at each instant (the rule in node.hpp): due ticks run in
// the order the nodes were added, then every message published or injected at that instant is
// delivered, in publish order, to every subscriber (messages published by handlers join the
// same queue). Same nodes, same inputs: same outputs, bit for bit.
// Steady-state delivery allocates nothing (queue slots and their buffers are reused).
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "runtime/event.hpp"
#include "runtime/node.hpp"

namespace tiller {

class LockstepExecutor {
 public:
  explicit LockstepExecutor(TimeUs start_us = 0);
  ~LockstepExecutor();

  // Adds a node (not owned). Its first tick is the first grid point at or after now().
  void add(Node& node);

  // Delivers a message from outside (a mission file, a test) at time `at` (>= now()).
  template <class Msg>
  void inject(const std::string& channel, const Msg& msg, TimeUs at) {
    Event e = encode(channel, at, msg);
    inject(std::move(e));
  }
  void inject(Event e);

  // Runs every tick and delivery with time <= end; afterwards now() == end.
  void run_until(TimeUs end);
  TimeUs now() const { return now_; }

  // Called for every delivered message (published or injected), e.g. to write a log.
  using Observer = std::function<void(const std::string& channel, const std::uint8_t* data,
                                      int size, TimeUs time)>;
  void observe(Observer o) { observers_.push_back(std::move(o)); }

 private:
  struct Slot {
    std::string channel;
    std::vector<std::uint8_t> data;
  };
  class QueueBus;
  void enqueue(std::string_view channel, const std::uint8_t* data, int size);
  void deliver_pending();

  TimeUs now_;
  std::vector<Node*> nodes_;
  std::vector<TimeUs> next_tick_;
  std::unordered_map<std::string, std::vector<Node*>> subscribers_;
  std::deque<Slot> pending_;  // deque: references stay valid while handlers publish
  std::size_t n_pending_ = 0;
  std::multimap<TimeUs, Event> injected_;
  std::vector<Observer> observers_;
  std::unique_ptr<QueueBus> bus_;
};

}  // namespace tiller
