#include "auth/verifier.hpp"

#include <sodium.h>

#include <cstring>
#include <functional>
#include <stdexcept>

namespace tiller::auth {

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::kSigned:
      return "signed";
    case Verdict::kUnsignedAccepted:
      return "unsigned_accepted";
    case Verdict::kUnsigned:
      return "unsigned";
    case Verdict::kWrongKey:
      return "wrong_key";
    case Verdict::kBadMac:
      return "bad_mac";
    case Verdict::kWindow:
      return "window";
    case Verdict::kReplay:
      return "replay";
    case Verdict::kStreamsFull:
      return "streams_full";
  }
  return "?";
}

Verifier::Verifier(Policy policy) : policy_(std::move(policy)) {
  if (policy_.require_signed && !policy_.key) {
    throw std::runtime_error(
        "require_signed is on but no key file was given (--key-file FILE or the launch file's "
        "key_file; make one with tiller-key new FILE)");
  }
  if (policy_.window_us <= 0) throw std::runtime_error("auth window must be > 0");
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

Checked Verifier::check(std::string_view channel, const std::uint8_t* data, int size, TimeUs now) {
  Checked c;
  c.payload_size = size;
  if (!has_trailer(data, size)) {
    c.verdict = policy_.require_signed ? Verdict::kUnsigned : Verdict::kUnsignedAccepted;
    return c;
  }
  c.payload_size = size - kTrailerSize;
  const std::uint8_t* t = data + c.payload_size;
  const TrailerFields f = read_trailer(t);
  c.stamp = f.time_us;
  if (!policy_.key) {  // nothing to check it with, and nothing required
    c.verdict = Verdict::kUnsignedAccepted;
    return c;
  }
  const Key& key = *policy_.key;
  if (f.key_id != key.id) {
    c.verdict = Verdict::kWrongKey;
    return c;
  }
  std::uint8_t mac[kMacBytes];
  compute_mac(key, channel, data, c.payload_size, t, mac);
  if (crypto_verify_16(mac, t + 28) != 0) {
    c.verdict = Verdict::kBadMac;
    return c;
  }
  const std::size_t h = std::hash<std::string_view>{}(channel);
  Stream* s = nullptr;
  for (int i = 0; i < n_streams_; ++i) {
    Stream& st = streams_[static_cast<std::size_t>(i)];
    if (st.channel_hash == h && std::memcmp(st.sender, t, kSenderBytes) == 0) {
      s = &st;
      break;
    }
  }
  if (s && f.time_us <= s->last) {
    c.verdict = Verdict::kReplay;
    return c;
  }
  if (f.time_us > now + policy_.window_us || f.time_us < now - policy_.window_us) {
    c.verdict = Verdict::kWindow;
    return c;
  }
  if (!s) {
    if (n_streams_ == kMaxStreams) {
      c.verdict = Verdict::kStreamsFull;
      return c;
    }
    s = &streams_[static_cast<std::size_t>(n_streams_++)];
    std::memcpy(s->sender, t, kSenderBytes);
    s->channel_hash = h;
  }
  s->last = f.time_us;
  c.sender = f.sender;
  c.verdict = Verdict::kSigned;
  return c;
}

}  // namespace tiller::auth
