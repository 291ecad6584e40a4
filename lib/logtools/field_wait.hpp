// tiller-log wait: waits until FIELD of the messages on CHANNEL has equalled VALUE (compared as
// text, FieldValue::to_string) for `hold_s` seconds; gives up after `timeout_s` seconds (a launch
// file's ends_with process: "mission done"). FieldWait is the logic, told each message's bytes
// and the time (us) and asked at any time for its verdict and progress lines; wait_live runs it
// on an LCM URL with the wall clock.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include "auth/verifier.hpp"
#include "logtools/lcm_schema.hpp"
#include "runtime/event.hpp"

namespace tiller::logtools {

struct WaitSpec {
  std::string channel, field, value;
  double hold_s = 0.0;       // the value must hold this long (s)
  double timeout_s = 600.0;  // from the start (s)
};

class FieldWait {
 public:
  enum class Verdict { kWaiting, kMet, kTimedOut };
  FieldWait(WaitSpec spec, TimeUs start);
  // A message on the channel (with its fingerprint); bytes that do not decode are ignored.
  void on_message(const std::uint8_t* data, std::size_t size, TimeUs now);
  Verdict verdict(TimeUs now) const;
  std::string start_line() const;  // "tiller-log: waiting for C.F == V (time limit 600 s)"
  // For kMet: "... == V after 12.0 s (held 5.0 s)"; for kTimedOut: "FAILED: ... (N messages;
  // last F = X)".
  std::string verdict_line(TimeUs now) const;
  // Every 10 s: "tiller-log: 20 s: segment=1 distance_to_goal=12.5 ..." (else nothing).
  std::optional<std::string> progress_line(TimeUs now);

 private:
  WaitSpec spec_;
  TimeUs start_;
  TimeUs next_note_;
  Decoded last_;
  bool have_ = false;
  std::optional<TimeUs> met_since_;
  std::int64_t messages_ = 0;
};

// Subscribes to spec.channel on `lcm_url` (TTL 0 unless given) and prints the start line, the
// progress lines and the verdict line to `out`; returns 0 when met, 1 on timeout. Signed
// messages are checked under `policy` (auth/verifier.hpp) and their trailer stripped; refused
// ones are ignored like undecodable ones.
int wait_live(const std::string& lcm_url, const WaitSpec& spec, std::FILE* out,
              const auth::Policy& policy = {});

}  // namespace tiller::logtools
