#include "runtime/lockstep.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace tiller {

class LockstepExecutor::QueueBus : public Bus {
 public:
  explicit QueueBus(LockstepExecutor& ex) : ex_(ex) {}
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    ex_.enqueue(channel, data, size);
  }

 private:
  LockstepExecutor& ex_;
};

LockstepExecutor::LockstepExecutor(TimeUs start_us)
    : now_(start_us), bus_(std::make_unique<QueueBus>(*this)) {}

LockstepExecutor::~LockstepExecutor() {
  for (Node* n : nodes_) n->attach(nullptr);
}

void LockstepExecutor::add(Node& node) {
  node.attach(bus_.get());
  nodes_.push_back(&node);
  next_tick_.push_back(node.next_tick_at_or_after(now_));
  for (const auto& ch : node.subscribed_channels()) subscribers_[ch].push_back(&node);
}

void LockstepExecutor::inject(Event e) {
  if (e.time < now_) throw std::invalid_argument("LockstepExecutor::inject: time in the past");
  const TimeUs t = e.time;
  injected_.emplace(t, std::move(e));
}

void LockstepExecutor::enqueue(std::string_view channel, const std::uint8_t* data, int size) {
  if (n_pending_ == pending_.size()) pending_.emplace_back();
  Slot& s = pending_[n_pending_++];
  s.channel.assign(channel);
  s.data.assign(data, data + size);
}

void LockstepExecutor::deliver_pending() {
  // Handlers may publish while we deliver: n_pending_ grows and the loop picks them up.
  for (std::size_t i = 0; i < n_pending_; ++i) {
    const Slot& s = pending_[i];
    const int size = static_cast<int>(s.data.size());
    for (const auto& o : observers_) o(s.channel, s.data.data(), size, now_);
    auto it = subscribers_.find(s.channel);
    if (it == subscribers_.end()) continue;
    for (Node* n : it->second) n->deliver(s.channel, s.data.data(), size, now_);
  }
  n_pending_ = 0;
}

void LockstepExecutor::run_until(TimeUs end) {
  for (;;) {
    TimeUs t = std::numeric_limits<TimeUs>::max();
    for (TimeUs nt : next_tick_) t = std::min(t, nt);
    if (!injected_.empty()) t = std::min(t, injected_.begin()->first);
    if (t > end) break;
    now_ = t;
    // Injected messages for this instant queue first, then tick outputs join behind them;
    // all are delivered after the ticks (ticks before deliveries at one instant).
    while (!injected_.empty() && injected_.begin()->first <= t) {
      const Event& e = injected_.begin()->second;
      enqueue(e.channel, e.data.data(), static_cast<int>(e.data.size()));
      injected_.erase(injected_.begin());
    }
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      if (next_tick_[i] == t) {
        nodes_[i]->tick(t);
        next_tick_[i] = t + nodes_[i]->tick_period();
      }
    }
    deliver_pending();
  }
  now_ = std::max(now_, end);
}

}  // namespace tiller
