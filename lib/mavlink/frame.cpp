// MAVLink 2 frames on the generated C library (mavlink/frame.hpp).
#include "mavlink/frame.hpp"

#include <cstring>

namespace tiller::mavlink {

FrameWriter::FrameWriter(std::uint8_t sysid, std::uint8_t compid, std::optional<Secret> secret,
                         std::uint8_t link_id)
    : sysid_(sysid), compid_(compid), link_(link_id), secret_(secret) {}

std::size_t FrameWriter::finish(mavlink_message_t& msg, TimeUs now, std::uint8_t* out) {
  if (!secret_) return mavlink_msg_to_send_buffer(out, &msg);
  // The library finalised it unsigned: set the flag, then the CRC over the header as sent.
  msg.incompat_flags |= MAVLINK_IFLAG_SIGNED;
  std::size_t n = mavlink_msg_to_send_buffer(out, &msg);  // header, payload, old CRC, old block
  const std::size_t crc_at = MAVLINK_NUM_HEADER_BYTES + msg.len;
  std::uint16_t crc = crc_calculate(out + 1, MAVLINK_CORE_HEADER_LEN);
  crc_accumulate_buffer(&crc, reinterpret_cast<const char*>(out + MAVLINK_NUM_HEADER_BYTES),
                        msg.len);
  const mavlink_msg_entry_t* e = mavlink_get_msg_entry(msg.msgid);
  crc_accumulate(e ? e->crc_extra : 0, &crc);
  out[crc_at] = static_cast<std::uint8_t>(crc & 0xFF);
  out[crc_at + 1] = static_cast<std::uint8_t>(crc >> 8);
  msg.checksum = crc;
  std::uint8_t* sig = out + crc_at + 2;
  std::uint64_t ts = signing_timestamp(now);
  if (ts <= last_ts_) ts = last_ts_ + 1;  // strictly increasing, whatever the clock does
  last_ts_ = ts;
  sig[0] = link_;
  for (int i = 0; i < 6; ++i) sig[1 + i] = static_cast<std::uint8_t>(ts >> (8 * i));
  signature_of(*secret_, out, crc_at + 2 + 7, sig + 7);
  std::memcpy(msg.signature, sig, kSignatureBytes);
  n = crc_at + 2 + kSignatureBytes;
  return n;
}

void FrameReader::reset() {
  status_.parse_state = MAVLINK_PARSE_STATE_IDLE;
  raw_n_ = 0;
}

bool FrameReader::feed(std::uint8_t c) {
  if (raw_n_ == sizeof raw_) {  // keep the last frame's worth
    std::memmove(raw_, raw_ + kMaxFrame, kMaxFrame);
    raw_n_ = kMaxFrame;
  }
  raw_[raw_n_++] = c;
  const std::uint8_t r = mavlink_frame_char_buffer(&rx_, &status_, c, &out_, nullptr);
  if (r == MAVLINK_FRAMING_INCOMPLETE) return false;
  const bool v1 = out_.magic == MAVLINK_STX_MAVLINK1;
  const bool is_signed = !v1 && (out_.incompat_flags & MAVLINK_IFLAG_SIGNED) != 0;
  const std::size_t n =
      v1 ? MAVLINK_CORE_HEADER_MAVLINK1_LEN + 3u + out_.len
         : MAVLINK_NUM_NON_PAYLOAD_BYTES + out_.len + (is_signed ? kSignatureBytes : 0u);
  frame_.msg = &out_;
  frame_.is_signed = is_signed;
  frame_.n = n <= raw_n_ ? n : raw_n_;
  frame_.bytes = raw_ + raw_n_ - frame_.n;
  if (r == MAVLINK_FRAMING_BAD_CRC)
    frame_.verdict = FrameVerdict::kBadCrc;
  else if (r == MAVLINK_FRAMING_BAD_SIGNATURE)
    frame_.verdict = FrameVerdict::kBadSignature;
  else
    frame_.verdict = v1 ? FrameVerdict::kMavlink1 : FrameVerdict::kOk;
  raw_n_ = 0;
  return true;
}

}  // namespace tiller::mavlink
