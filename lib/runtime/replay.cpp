#include "runtime/replay.hpp"

namespace tiller {

class ReplayExecutor::CollectBus : public Bus {
 public:
  explicit CollectBus(ReplayExecutor& ex) : ex_(ex) {}
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    ex_.outputs_.push_back(
        Event{std::string(channel), ex_.now_, std::vector<std::uint8_t>(data, data + size)});
  }

 private:
  ReplayExecutor& ex_;
};

ReplayExecutor::ReplayExecutor(Node& node)
    : node_(node), bus_(std::make_unique<CollectBus>(*this)) {
  node_.attach(bus_.get());
}

ReplayExecutor::~ReplayExecutor() {
  node_.attach(nullptr);
}

void ReplayExecutor::run(const std::vector<Event>& log, std::optional<TimeUs> start,
                         std::optional<TimeUs> end) {
  if (log.empty() && (!start || !end)) return;
  const TimeUs t0 = start ? *start : log.front().time;
  const TimeUs t1 = end ? *end : log.back().time;
  TimeUs next_tick = node_.next_tick_at_or_after(t0);
  for (const Event& e : log) {
    if (e.time < t0) continue;
    if (e.time > t1) break;
    while (next_tick <= e.time) {
      now_ = next_tick;
      node_.tick(now_);
      next_tick += node_.tick_period();
    }
    if (!node_.subscribes_to(e.channel)) continue;
    now_ = e.time;
    node_.deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), now_);
  }
  while (next_tick <= t1) {
    now_ = next_tick;
    node_.tick(now_);
    next_tick += node_.tick_period();
  }
}

}  // namespace tiller
