#include "logtools/field_wait.hpp"

#include <lcm/lcm-cpp.hpp>

#include <cstdarg>
#include <stdexcept>

#include "runtime/live.hpp"

namespace tiller::logtools {

namespace {
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return buf;
}
}  // namespace

FieldWait::FieldWait(WaitSpec spec, TimeUs start)
    : spec_(std::move(spec)), start_(start), next_note_(start + 10 * kUsPerSecond) {}

void FieldWait::on_message(const std::uint8_t* data, std::size_t size, TimeUs now) {
  Decoded d;
  if (!tiller_types().decode(data, size, d)) return;
  ++messages_;
  const FieldValue* f = d.find(spec_.field);
  const bool met = f && f->to_string() == spec_.value;
  if (met && !met_since_) met_since_ = now;
  if (!met) met_since_.reset();
  last_ = std::move(d);
  have_ = true;
}

FieldWait::Verdict FieldWait::verdict(TimeUs now) const {
  if (met_since_ && to_seconds(now - *met_since_) >= spec_.hold_s) return Verdict::kMet;
  if (to_seconds(now - start_) >= spec_.timeout_s) return Verdict::kTimedOut;
  return Verdict::kWaiting;
}

std::string FieldWait::start_line() const {
  return format(
      "tiller-log: waiting for %s.%s == %s%s (time limit %.0f s)\n", spec_.channel.c_str(),
      spec_.field.c_str(), spec_.value.c_str(),
      spec_.hold_s > 0
          ? (", then " + std::to_string(static_cast<int>(spec_.hold_s)) + " s more").c_str()
          : "",
      spec_.timeout_s);
}

std::string FieldWait::verdict_line(TimeUs now) const {
  if (verdict(now) == Verdict::kMet)
    return format("tiller-log: %s.%s == %s after %.1f s (held %.1f s)\n", spec_.channel.c_str(),
                  spec_.field.c_str(), spec_.value.c_str(), to_seconds(*met_since_ - start_),
                  to_seconds(now - *met_since_));
  std::string s =
      format("tiller-log: FAILED: %s.%s never == %s for %.0f s within %.0f s (%lld messages",
             spec_.channel.c_str(), spec_.field.c_str(), spec_.value.c_str(), spec_.hold_s,
             spec_.timeout_s, static_cast<long long>(messages_));
  if (have_) {
    const auto* v = last_.find(spec_.field);
    s += "; last " + spec_.field + " = " + (v ? v->to_string() : "(absent)");
  }
  return s + ")\n";
}

std::optional<std::string> FieldWait::progress_line(TimeUs now) {
  if (now < next_note_) return std::nullopt;
  next_note_ = now + 10 * kUsPerSecond;
  std::string s = format("tiller-log: %.0f s:", to_seconds(now - start_));
  if (!have_) s += " nothing on " + spec_.channel + " yet";
  for (const char* k :
       {"segment", "n_waypoints", "distance_to_goal", "cross_track_error", spec_.field.c_str()}) {
    if (const auto* v = have_ ? last_.find(k) : nullptr)
      s += format(" %s=%.6g", k, v->is_text ? 0.0 : v->number);
  }
  return s + "\n";
}

int wait_live(const std::string& lcm_url, const WaitSpec& spec, std::FILE* out,
              const auth::Policy& policy) {
  lcm::LCM lc(with_default_ttl(lcm_url));
  if (!lc.good()) throw std::runtime_error("cannot open LCM at " + lcm_url);
  FieldWait wait(spec, wall_time_us());
  auth::Verifier verifier(policy);
  struct Handler {
    FieldWait* w;
    auth::Verifier* v;
    void on(const lcm::ReceiveBuffer* rb, const std::string& channel) {
      const auto* bytes = static_cast<const std::uint8_t*>(rb->data);
      const TimeUs now = wall_time_us();
      const auth::Checked c = v->check(channel, bytes, static_cast<int>(rb->data_size), now);
      if (auth::accepted(c.verdict))
        w->on_message(bytes, static_cast<std::size_t>(c.payload_size), now);
    }
  } handler{&wait, &verifier};
  lc.subscribe(spec.channel, &Handler::on, &handler);
  std::fputs(wait.start_line().c_str(), out);
  std::fflush(out);
  for (;;) {
    lc.handleTimeout(100);
    const TimeUs now = wall_time_us();
    if (const auto v = wait.verdict(now); v != FieldWait::Verdict::kWaiting) {
      std::fputs(wait.verdict_line(now).c_str(), out);
      return v == FieldWait::Verdict::kMet ? 0 : 1;
    }
    if (const auto line = wait.progress_line(now)) {
      std::fputs(line->c_str(), out);
      std::fflush(out);
    }
  }
}

}  // namespace tiller::logtools
