// MAVLink 2 frames in and out, on the generated C library (mavlink/mavlink_c.hpp): no byte of a
// frame is packed here by hand and no CRC table is typed; signing is mavlink/signing.hpp's.
//
// FrameWriter: a message packed by a generated *_pack_status / *_encode_status function (with
// status()) becomes the bytes of one frame, signed when a secret is set: the signed flag set, the
// CRC computed again over the new header (the library's crc_calculate with the message's
// CRC_EXTRA), the signature block appended. Sequence numbers count per writer.
// FrameReader: bytes in (a UDP datagram, or a serial stream piece by piece), each complete frame
// out with its verdict: OK, bad CRC (or an unknown message id), bad signature, a MAVLink 1 frame.
// Pure, and no allocation after construction.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "mavlink/mavlink_c.hpp"
#include "mavlink/signing.hpp"

namespace tiller::mavlink {

inline constexpr std::size_t kMaxFrame = MAVLINK_MAX_PACKET_LEN;

class FrameWriter {
 public:
  FrameWriter(std::uint8_t sysid, std::uint8_t compid, std::optional<Secret> secret,
              std::uint8_t link_id = 0);
  std::uint8_t sysid() const { return sysid_; }
  std::uint8_t compid() const { return compid_; }
  // The status the generated pack functions take (sequence numbers).
  mavlink_status_t* status() { return &status_; }
  // The frame of a packed message into out (kMaxFrame bytes); returns its length.
  std::size_t finish(mavlink_message_t& msg, TimeUs now, std::uint8_t* out);
  // A new secret (SETUP_SIGNING): frames are signed with it from now, their timestamps at least
  // `initial` (10 us units since 2015) and still increasing.
  void set_secret(const Secret& secret, std::uint64_t initial) {
    secret_ = secret;
    if (initial > last_ts_) last_ts_ = initial;
  }

 private:
  std::uint8_t sysid_, compid_, link_;
  std::optional<Secret> secret_;
  mavlink_status_t status_{};
  std::uint64_t last_ts_ = 0;
};

enum class FrameVerdict { kOk, kBadCrc, kBadSignature, kMavlink1 };

class FrameReader {
 public:
  struct Frame {
    FrameVerdict verdict;
    const mavlink_message_t* msg;
    bool is_signed;
    const std::uint8_t* bytes;  // the frame as received (n bytes)
    std::size_t n;
  };
  // Feeds one byte; returns true when a frame ended with it (then frame() tells it).
  bool feed(std::uint8_t c);
  const Frame& frame() const { return frame_; }
  // Forgets a partial frame (a new UDP datagram starts afresh).
  void reset();
  std::int64_t parse_errors() const { return status_.parse_error; }

 private:
  mavlink_message_t rx_{}, out_{};
  mavlink_status_t status_{};
  std::uint8_t raw_[2 * kMaxFrame] = {};
  std::size_t raw_n_ = 0;
  Frame frame_{FrameVerdict::kOk, &out_, false, raw_, 0};
};

}  // namespace tiller::mavlink
