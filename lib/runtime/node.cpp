#include "runtime/node.hpp"

#include <algorithm>
#include <cctype>

#include "runtime/channels.hpp"

namespace tiller {

Node::Node(std::string name, TimeUs tick_period_us)
    : name_(std::move(name)), tick_period_(tick_period_us > 0 ? tick_period_us : kUsPerSecond) {
  heartbeat_channel_ = channels::kHeartbeatPrefix;
  for (char c : name_) {
    heartbeat_channel_ +=
        (c == '-') ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  heartbeat_.process = name_;
  heartbeat_.state = heartbeat_t::STATE_OK;
  heartbeat_.status = "starting";
}

Node::~Node() = default;

std::vector<std::string> Node::subscribed_channels() const {
  std::vector<std::string> out;
  for (const auto& kv : subs_) out.push_back(kv.first);
  std::sort(out.begin(), out.end());
  return out;
}

void Node::deliver(const std::string& channel, const void* data, int size, TimeUs now) {
  auto it = subs_.find(channel);
  if (it == subs_.end()) return;
  ++received_;
  bool ok = false;
  try {
    ok = it->second->dispatch(data, size, now);
  } catch (...) {
    // Generated decoders do not throw, and handlers must not; if one does, the message is
    // dropped and counted rather than taking the process down.
    ok = false;
  }
  if (!ok) reject(*it->second->malformed);
}

void Node::tick(TimeUs now) {
  on_tick(now);
  if (now >= next_heartbeat_) {
    publish_heartbeat(now);
    next_heartbeat_ = (now / kUsPerSecond + 1) * kUsPerSecond;
  }
}

TimeUs Node::next_tick_at_or_after(TimeUs t) const {
  TimeUs k = t / tick_period_;
  if (k * tick_period_ < t) ++k;
  if (t < 0 && k * tick_period_ - tick_period_ >= t) --k;
  return k * tick_period_;
}

std::int64_t& Node::counter(const std::string& name) {
  return counters_[name];
}

std::int64_t Node::counter_value(const std::string& name) const {
  auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

void Node::set_health(std::int8_t state, const std::string& status) {
  heartbeat_.state = state;
  if (heartbeat_.status != status) heartbeat_.status = status;
}

void Node::publish_bytes(std::string_view channel, const std::uint8_t* data, int size) {
  ++published_;
  if (bus_) bus_->publish(channel, data, size);
}

void Node::publish_heartbeat(TimeUs now) {
  heartbeat_.utime = now;
  heartbeat_.received = received_;
  heartbeat_.rejected = rejected_;
  heartbeat_.stale = stale_;
  heartbeat_.published = published_;
  heartbeat_.n_counters = static_cast<std::int32_t>(counters_.size());
  heartbeat_.counter_names.resize(counters_.size());
  heartbeat_.counter_values.resize(counters_.size());
  std::size_t i = 0;
  for (const auto& kv : counters_) {
    if (heartbeat_.counter_names[i] != kv.first) heartbeat_.counter_names[i] = kv.first;
    heartbeat_.counter_values[i] = kv.second;
    ++i;
  }
  publish(heartbeat_channel_, heartbeat_);
}

}  // namespace tiller
