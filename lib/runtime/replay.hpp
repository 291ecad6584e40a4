// Log replay executor: feeds a node the recorded inputs from a log, with their recorded times,
// ticks it on its grid in between (due ticks before deliveries at one instant, as in
// node.hpp), and collects what it publishes. For a log written by the lockstep executor the
// outputs are identical, bit for bit, to those recorded; for a live log they are today's code's
// answer to yesterday's inputs (tiller-replay compares them).
#pragma once

#include <optional>
#include <vector>

#include "runtime/event.hpp"
#include "runtime/node.hpp"

namespace tiller {

class ReplayExecutor {
 public:
  explicit ReplayExecutor(Node& node);
  ~ReplayExecutor();

  // Replays `log` (sorted by time). Only events on channels the node subscribes to are fed.
  // Ticks run from the first grid point at or after `start` (default: the first event's time)
  // up to `end` (default: the last event's time).
  void run(const std::vector<Event>& log, std::optional<TimeUs> start = std::nullopt,
           std::optional<TimeUs> end = std::nullopt);

  // Everything the node published, in order, stamped with the time it was published.
  const std::vector<Event>& outputs() const { return outputs_; }

 private:
  class CollectBus;
  Node& node_;
  TimeUs now_ = 0;
  std::vector<Event> outputs_;
  std::unique_ptr<CollectBus> bus_;
};

}  // namespace tiller
