// MAVLink 2 message signing (https://mavlink.io/en/guide/message_signing.html) with libsodium's
// SHA-256 (crypto_hash_sha256): a frame's 13-byte signature block is
//   link id (1 byte) | timestamp (6 bytes, little-endian, units of 10 us since 2015-01-01 UTC)
//   | the first 6 bytes of SHA-256(secret key (32 bytes) | header | payload | CRC | link id |
//     timestamp)
// A receiver keeps the last timestamp of each stream (system id, component id, link id): a frame
// is accepted when its signature verifies and its timestamp is newer than its stream's last (a new
// stream: not more than a minute older than the newest timestamp seen), as the spec says.
// Pure: the time is an argument; nothing allocates after construction.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/time.hpp"

namespace tiller::mavlink {

inline constexpr std::size_t kSecretBytes = 32;
using Secret = std::array<std::uint8_t, kSecretBytes>;
inline constexpr std::size_t kSignatureBytes = 13;
// 2015-01-01 00:00:00 UTC in us since 1970 (the signing epoch).
inline constexpr TimeUs kSigningEpochUs = 1420070400LL * 1000000LL;
// A new stream's first timestamp may be this much older than the newest seen (10 us units: 60 s).
inline constexpr std::uint64_t kNewStreamLimit = 6000000;

// The signing timestamp for a wall time in us since 1970 (10 us units since 2015).
std::uint64_t signing_timestamp(TimeUs now);

// The 6-byte signature of `frame` (header + payload + CRC, then link id and timestamp: the frame's
// first n - 6 bytes when n is its signed length).
void signature_of(const Secret& key, const std::uint8_t* frame, std::size_t signed_part,
                  std::uint8_t out[6]);

enum class SignatureVerdict { kOk, kBadSignature, kReplay, kOld, kStreamsFull };
const char* verdict_name(SignatureVerdict v);

class SignatureChecker {
 public:
  static constexpr int kMaxStreams = 32;
  explicit SignatureChecker(const Secret& key) : key_(key) {}
  // `frame`, `n` bytes: a whole signed MAVLink 2 frame (signature block last), received at `now`
  // (us since 1970: the local timestamp is the newer of the clock and the newest accepted).
  SignatureVerdict check(const std::uint8_t* frame, std::size_t n, TimeUs now);
  std::uint64_t newest() const { return newest_; }
  // A new secret (SETUP_SIGNING): the streams are forgotten (each starts again under the new key)
  // and no timestamp older than `initial` (10 us units since 2015), less the new-stream limit,
  // is accepted.
  void rekey(const Secret& key, std::uint64_t initial) {
    key_ = key;
    n_streams_ = 0;
    if (initial > newest_) newest_ = initial;
  }

 private:
  struct Stream {
    std::uint8_t sysid = 0, compid = 0, link = 0;
    std::uint64_t last = 0;
  };
  Secret key_;
  std::array<Stream, kMaxStreams> streams_{};
  int n_streams_ = 0;
  std::uint64_t newest_ = 0;
};

}  // namespace tiller::mavlink
