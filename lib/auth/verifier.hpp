// The receiving side of message signing: what a process accepts (Policy) and the per-stream
// replay state (Verifier). A stream is one (sender, channel) pair, as MAVLink 2 keeps one per
// (system, component, link) (https://mavlink.io/en/guide/message_signing.html). A signed
// message is accepted only if
//   1. its key id is this process's key's (else kWrongKey), and
//   2. its MAC verifies (else kBadMac), and
//   3. its stamp is greater than the last accepted one of its stream (else kReplay), and
//   4. its time stamp is within window_us of the receiver's clock, either way (else kWindow):
//      this bounds how old a captured message can be and still count (and so how long a new
//      or restarted receiver is open to a replay), and refuses the queued input of a process
//      that was stopped for longer than the window.
// Without a trailer a message is kUnsigned when signing is required, else kUnsignedAccepted.
// No allocation after construction: streams live in a fixed table (kMaxStreams; a further
// stream is refused as kStreamsFull, counted, never evicting one that is known).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "auth/key.hpp"
#include "auth/trailer.hpp"
#include "core/time.hpp"

namespace tiller::auth {

// What a process signs with and accepts. Filled from --key-file / --require-signed /
// --auth-window-s (or TILLER_KEY_FILE / TILLER_REQUIRE_SIGNED / TILLER_AUTH_WINDOW_S, which
// tiller-launch sets from the launch file's key_file / require_signed / auth_window_s).
struct Policy {
  std::optional<Key> key;           // sign outputs and verify inputs with it
  bool require_signed = false;      // refuse messages without a valid trailer
  TimeUs window_us = 1'000'000;     // |stamp - receive time| limit (clock offset + latency)
  std::string key_file;             // where the key came from (for messages)
  std::string raw_sender = "tool";  // sender of messages a tool publishes without a node
  // Not signing: the bound on the clock offset between computers that every node allows on a
  // message's own utime (Node::on_time; --clock-offset-s / TILLER_CLOCK_OFFSET_S). It
  // rides here because the live executor takes one policy for what its process accepts.
  TimeUs clock_offset_us = kDefaultClockOffsetUs;
  bool enabled() const { return key.has_value() || require_signed; }
};

enum class Verdict : std::uint8_t {
  kSigned,            // valid trailer: accept, sender known
  kUnsignedAccepted,  // no trailer (or one this process cannot check), signing not required
  kUnsigned,          // refused: no trailer and signing required
  kWrongKey,          // refused: signed with another key
  kBadMac,            // refused: MAC does not verify (tampered or forged)
  kWindow,            // refused: stamp further than the window from the receive time
  kReplay,            // refused: stamp not newer than the stream's last accepted one
  kStreamsFull,       // refused: no room for another stream
};
inline constexpr int kVerdicts = 8;
// "signed", "unsigned", "wrong_key", ... (the counter suffix: rejected.auth.<name>).
const char* to_string(Verdict v);
inline bool accepted(Verdict v) {
  return v == Verdict::kSigned || v == Verdict::kUnsignedAccepted;
}

struct Checked {
  Verdict verdict = Verdict::kUnsigned;
  int payload_size = 0;     // bytes of the LCM message (the trailer stripped)
  std::string_view sender;  // kSigned: the authenticated sender (a view into the packet)
  TimeUs stamp = 0;         // the trailer's time stamp, if there was a trailer
};

class Verifier {
 public:
  static constexpr int kMaxStreams = 256;
  explicit Verifier(Policy policy);
  const Policy& policy() const { return policy_; }
  // Checks one received packet on `channel`, received at `now` (us since the epoch).
  Checked check(std::string_view channel, const std::uint8_t* data, int size, TimeUs now);
  int streams() const { return n_streams_; }

 private:
  struct Stream {
    std::uint8_t sender[kSenderBytes];
    std::size_t channel_hash;
    TimeUs last;
  };
  Policy policy_;
  std::array<Stream, kMaxStreams> streams_{};
  int n_streams_ = 0;
};

}  // namespace tiller::auth
