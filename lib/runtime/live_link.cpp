#include "runtime/live_link.hpp"

#include <poll.h>

#include <algorithm>
#include <stdexcept>

#include "runtime/live.hpp"

namespace tiller {

LiveLink::LiveLink(const std::string& url, const auth::Policy& policy, Node& node)
    : verifier_(policy), node_(node) {
  const std::string u = with_default_ttl(url);
  lcm_ = lcm_create(u.c_str());
  if (lcm_ == nullptr)
    throw std::runtime_error("cannot open LCM at '" + u +
                             "' (no multicast route? see docs/troubleshooting.md)");
  if (policy.key) signer_.emplace(*policy.key, node_.name());
  for (int v = 0; v < auth::kVerdicts; ++v) {
    const auto verdict = static_cast<auth::Verdict>(v);
    if (!auth::accepted(verdict) && policy.enabled())
      refused_[static_cast<std::size_t>(v)] =
          &node_.executor_counter(std::string("rejected.auth.") + auth::to_string(verdict));
  }
  if (policy.key) sender_ = &node_.executor_counter("rejected.auth.sender");
  for (const auto& ch : node_.subscribed_channels())
    lcm_subscribe(lcm_, ch.c_str(), &LiveLink::on_message, this);
  node_.attach(this);
  next_tick_ = node_.next_tick_at_or_after(wall_time_us());
}

LiveLink::~LiveLink() {
  node_.attach(nullptr);
  lcm_destroy(lcm_);
}

int LiveLink::fd() const {
  return lcm_get_fileno(lcm_);
}

void LiveLink::on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
  auto* self = static_cast<LiveLink*>(user);
  const TimeUs now = wall_time_us();
  const std::string_view ch(channel);
  const auto* data = static_cast<const std::uint8_t*>(rbuf->data);
  const auth::Checked c = self->verifier_.check(ch, data, static_cast<int>(rbuf->data_size), now);
  Node& m = self->node_;
  if (!auth::accepted(c.verdict)) {
    if (std::int64_t* n = self->refused_[static_cast<std::size_t>(c.verdict)])
      m.count_transport_reject(*n);
    return;
  }
  if (self->verifier_.policy().key) {
    const auto* allowed = m.allowed_senders(ch);
    if (allowed && (c.verdict != auth::Verdict::kSigned ||
                    std::find(allowed->begin(), allowed->end(), c.sender) == allowed->end())) {
      m.count_transport_reject(*self->sender_);
      return;
    }
  }
  m.deliver(ch, data, c.payload_size, now);
}

void LiveLink::handle() {
  pollfd p{fd(), POLLIN, 0};
  // What queued up, then back to the host's loop (bounded: a flood of traffic must not starve
  // it).
  for (int k = 0; k < 1000 && ::poll(&p, 1, 0) > 0 && (p.revents & POLLIN); ++k) {
    if (lcm_handle(lcm_) != 0) break;
  }
  tick(wall_time_us());
}

void LiveLink::tick(TimeUs now) {
  if (now < next_tick_) return;
  const TimeUs period = node_.tick_period();
  const TimeUs behind = (now - next_tick_) / period;
  const TimeUs t = next_tick_ + behind * period;
  next_tick_ = t + period;
  node_.count_missed_ticks(behind);
  node_.tick(t);
}

void LiveLink::publish(std::string_view channel, const std::uint8_t* data, int size) {
  channel_.assign(channel);
  if (!signer_) {
    lcm_publish(lcm_, channel_.c_str(), data, static_cast<unsigned>(size));
    return;
  }
  const auto n = static_cast<std::size_t>(size) + auth::kTrailerSize;
  if (buf_.size() < n) buf_.resize(n);
  std::copy(data, data + size, buf_.begin());
  signer_->sign(channel, data, size, wall_time_us(), buf_.data() + size);
  lcm_publish(lcm_, channel_.c_str(), buf_.data(), static_cast<unsigned>(n));
}

}  // namespace tiller
