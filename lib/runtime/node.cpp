#include "runtime/node.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <stdexcept>

#include "runtime/channels.hpp"
#include "runtime/heartbeat_name.hpp"

namespace tiller {

std::string heartbeat_channel_of(const std::string& node_name) {
  std::string s = channels::kHeartbeatPrefix;
  for (char c : node_name)
    s += (c == '-') ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

Node::Node(std::string name, TimeUs tick_period_us)
    : name_(std::move(name)),
      tick_period_(tick_period_us > 0 ? tick_period_us : kUsPerSecond),
      heartbeat_channel_(heartbeat_channel_of(name_)) {
  heartbeat_.process = name_;
  heartbeat_.state = heartbeat_t::STATE_OK;
  heartbeat_.status = "starting";
  adverts_.push_back(Advert{heartbeat_channel_, heartbeat_t::getTypeName()});
}

Node::~Node() = default;

std::vector<std::string> Node::subscribed_channels() const {
  std::vector<std::string> out;
  for (const auto& sub : subs_) out.push_back(sub->channel);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> Node::published_channels() const {
  std::vector<std::string> out;
  for (const auto& a : adverts_) out.push_back(a.channel);
  std::sort(out.begin(), out.end());
  return out;
}

std::string Node::subscribed_type(std::string_view channel) const {
  const SubscriptionBase* s = find_sub(channel);
  return s ? s->type : "";
}

std::string Node::published_type(std::string_view channel) const {
  for (const auto& a : adverts_)
    if (a.channel == channel) return a.type;
  return "";
}

bool Node::advertises(std::string_view channel) const {
  for (const auto& a : adverts_)
    if (a.channel == channel) return true;
  return false;
}

const std::vector<std::string>* Node::allowed_senders(std::string_view channel) const {
  const SubscriptionBase* s = find_sub(channel);
  return (s && !s->senders.empty()) ? &s->senders : nullptr;
}

void Node::accept_only_from(std::string_view channel, std::vector<std::string> senders) {
  SubscriptionBase* s = find_sub(channel);
  if (!s) {
    throw std::logic_error(name_ + ": accept_only_from(" + std::string(channel) +
                           ") before subscribing to it");
  }
  if (senders.empty()) {
    throw std::invalid_argument(name_ + ": accept_only_from(" + std::string(channel) +
                                ") needs at least one sender");
  }
  s->senders = std::move(senders);
}

Node::SubscriptionBase* Node::find_sub(std::string_view channel) const {
  for (const auto& s : subs_)
    if (s->channel == channel) return s.get();
  return nullptr;
}

void Node::add_sub(const std::string& channel, const char* type,
                   std::unique_ptr<SubscriptionBase> s) {
  s->channel = channel;
  s->type = type;
  s->malformed = &counter("malformed." + channel);
  for (auto& old : subs_) {
    if (old->channel == channel) {
      old = std::move(s);  // a second subscribe() to one channel replaces the first
      return;
    }
  }
  subs_.push_back(std::move(s));
}

void Node::advertise_type(const std::string& channel, const char* type) {
  for (auto& a : adverts_) {
    if (a.channel == channel) {
      a.type = type;
      return;
    }
  }
  adverts_.push_back(Advert{channel, type});
}

void Node::deliver(std::string_view channel, const void* data, int size, TimeUs now) {
  SubscriptionBase* sub = find_sub(channel);
  if (!sub) return;
  ++received_;
  bool ok = false;
  try {
    ok = sub->dispatch(data, size, now);
  } catch (const std::exception& e) {
    // Handlers must not throw (a throwing decoder is caught in dispatch() and counted as
    // malformed); if one does, the message is dropped and counted rather than taking the
    // process down, and the heartbeat latches FAULT.
    if (!exception_message_) exception_message_ = &counter("exception.message");
    reject(*exception_message_);
    latch_fault(e.what());
    return;
  } catch (...) {
    if (!exception_message_) exception_message_ = &counter("exception.message");
    reject(*exception_message_);
    latch_fault("unknown exception");
    return;
  }
  if (!ok) reject(*sub->malformed);
}

void Node::latch_fault(std::string_view what) {
  faulted_ = true;
  fault_status_ = "FAULT: exception: ";
  fault_status_ += what;
}

void Node::record_fault(const std::string& counter_name, const std::string& what) {
  ++counter(counter_name);
  latch_fault(what);
}

void Node::count_missed_ticks(std::int64_t n) {
  // The live executor calls this before every tick it runs: count that tick too, so the
  // fraction of missed ticks can be told from a heartbeat (tiller-log summary). A map lookup of
  // a short (SSO) name: no allocation after the first tick. "ticks.missed" is made on the first
  // tick too: made on the first miss, it allocated whenever a loaded machine first made the
  // loop fall behind, long after start-up.
  ++counter("ticks.run");
  if (!ticks_missed_) ticks_missed_ = &counter("ticks.missed");
  if (n > 0) *ticks_missed_ += n;
}

bool Node::tick(TimeUs now) {
  bool ok = true;
  try {
    on_tick(now);
  } catch (const std::exception& e) {
    ok = false;
    latch_fault(e.what());
  } catch (...) {
    ok = false;
    latch_fault("unknown exception");
  }
  if (!ok) {
    if (!exception_tick_) exception_tick_ = &counter("exception.tick");
    ++*exception_tick_;
  }
  if (now >= next_heartbeat_) {
    publish_heartbeat(now);
    next_heartbeat_ = (now / kUsPerSecond + 1) * kUsPerSecond;
  }
  return ok;
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

bool Node::on_time(TimeUs utime, TimeUs now, TimeUs limit, std::string_view input) {
  const Arrival a = arrival_of(now, utime, limit, clock_offset_);
  if (a == Arrival::kAccepted) return true;
  // The name is built in place and looked up without a std::string: a burst of refused
  // messages (a resumed process's queue) allocates only for the first of each kind.
  char name[96];
  const int n = std::snprintf(name, sizeof name, "rejected.%.*s.%s", static_cast<int>(input.size()),
                              input.data(), a == Arrival::kStale ? "stale" : "future");
  const std::string_view key(name, static_cast<std::size_t>(std::clamp(n, 0, 95)));
  auto it = counters_.find(key);
  if (it == counters_.end()) it = counters_.emplace(std::string(key), 0).first;
  return reject(it->second);
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
  if (!advertises(channel)) {
    std::int64_t* c = nullptr;
    for (auto& u : unadvertised_)
      if (u.first == channel) c = u.second;
    if (!c) {
      const std::string name(channel);
      c = &counter("unadvertised." + name);
      unadvertised_.emplace_back(name, c);
    }
    ++*c;
  }
  ++published_;
  if (bus_) bus_->publish(channel, data, size);
}

void Node::publish_heartbeat(TimeUs now) {
  heartbeat_.utime = now;
  if (faulted_) {
    heartbeat_.state = heartbeat_t::STATE_FAULT;  // latched: a node that threw stays suspect
    if (heartbeat_.status != fault_status_) heartbeat_.status = fault_status_;
  }
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
