// The signed-message trailer: 48 bytes appended after an LCM message's encoded bytes by the
// live executor's transport (lib/runtime/live.cpp), modelled on MAVLink 2 message signing
// (https://mavlink.io/en/guide/message_signing.html: a link id, a 48-bit timestamp that grows
// with every message of a stream, a truncated keyed hash). LCM decoders read a message from
// the front and ignore bytes after it (lcm-spy's Java decoder among them), so a signed message
// still decodes everywhere; Tiller's own receivers verify and strip the trailer first.
//
// Layout (offsets from the trailer's first byte; integers big-endian like LCM's):
//    0..15  sender   the publishing node's name, ASCII, NUL-padded (at most 16 bytes)
//   16..23  time_us  int64, us since 1970-01-01 UTC (CLOCK_REALTIME), strictly increasing for
//                    every message one sender signs
//   24..27  key_id   uint32, the signing key's public id (auth/key.hpp)
//   28..43  mac      16 bytes: BLAKE2b (libsodium crypto_generichash) keyed with the 32-byte
//                    key, 16-byte output, over
//                      magic | u32 channel length | channel | u32 payload length | payload |
//                      trailer bytes 0..27
//   44..47  magic    7E 54 53 01 ("~TS" and format version 1)
// So the channel name, every payload byte, the sender and the time are authenticated: a
// message moved to another channel, a changed byte, another sender's name or a new time all
// fail the MAC.
#pragma once

#include <cstdint>
#include <string_view>

#include "auth/key.hpp"
#include "core/time.hpp"

namespace tiller::auth {

inline constexpr int kTrailerSize = 48;
inline constexpr int kSenderBytes = 16;
inline constexpr int kMacBytes = 16;
inline constexpr std::uint8_t kMagic[4] = {0x7E, 0x54, 0x53, 0x01};

// True when the last bytes of `data` are a trailer's magic (size >= kTrailerSize).
bool has_trailer(const std::uint8_t* data, int size);

// The size of the LCM message in `data`: size - kTrailerSize when it ends in a trailer, else
// size. For readers of logs and tools that decode without verifying.
int payload_size(const std::uint8_t* data, int size);

// A trailer's fields, read without verifying (views into the packet).
struct TrailerFields {
  std::string_view sender;  // NULs stripped
  TimeUs time_us = 0;
  std::uint32_t key_id = 0;
};
TrailerFields read_trailer(const std::uint8_t* trailer);

// Whether `sender` fits the trailer's sender field (1..16 bytes, printable ASCII).
bool valid_sender(std::string_view sender);

// Signs the messages of one sender. Not thread-safe; allocation-free.
class Signer {
 public:
  // Throws std::invalid_argument if `sender` is not valid_sender().
  Signer(const Key& key, std::string_view sender);
  // Writes the trailer for `payload` on `channel` into out[0..kTrailerSize), stamped
  // max(now, last stamp + 1) so stamps grow strictly even if the clock stands still or steps
  // back. Returns the stamp.
  TimeUs sign(std::string_view channel, const std::uint8_t* payload, int size, TimeUs now,
              std::uint8_t* out);
  TimeUs last_stamp() const { return last_; }

 private:
  Key key_;
  std::uint8_t sender_[kSenderBytes] = {};
  TimeUs last_ = 0;
};

// The MAC of (channel, payload, trailer bytes 0..27) under `key` into mac[kMacBytes].
void compute_mac(const Key& key, std::string_view channel, const std::uint8_t* payload, int size,
                 const std::uint8_t* trailer_head, std::uint8_t* mac);

}  // namespace tiller::auth
