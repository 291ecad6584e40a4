// MAVLink 2 signatures with libsodium (mavlink/signing.hpp).
#include "mavlink/signing.hpp"

#include <sodium.h>

#include <cstring>

namespace tiller::mavlink {

std::uint64_t signing_timestamp(TimeUs now) {
  return now <= kSigningEpochUs ? 0 : static_cast<std::uint64_t>(now - kSigningEpochUs) / 10;
}

void signature_of(const Secret& key, const std::uint8_t* frame, std::size_t signed_part,
                  std::uint8_t out[6]) {
  crypto_hash_sha256_state st;
  crypto_hash_sha256_init(&st);
  crypto_hash_sha256_update(&st, key.data(), key.size());
  crypto_hash_sha256_update(&st, frame, signed_part);
  unsigned char h[crypto_hash_sha256_BYTES];
  crypto_hash_sha256_final(&st, h);
  std::memcpy(out, h, 6);
}

const char* verdict_name(SignatureVerdict v) {
  switch (v) {
    case SignatureVerdict::kOk:
      return "ok";
    case SignatureVerdict::kBadSignature:
      return "bad_signature";
    case SignatureVerdict::kReplay:
      return "replay";
    case SignatureVerdict::kOld:
      return "old_timestamp";
    case SignatureVerdict::kStreamsFull:
      return "streams_full";
  }
  return "?";
}

SignatureVerdict SignatureChecker::check(const std::uint8_t* frame, std::size_t n, TimeUs now) {
  const std::uint64_t local = signing_timestamp(now);
  if (local > newest_) newest_ = local;
  if (n < 10 + 2 + kSignatureBytes) return SignatureVerdict::kBadSignature;
  const std::uint8_t* sig = frame + n - kSignatureBytes;
  std::uint8_t expect[6];
  signature_of(key_, frame, n - 6, expect);
  if (sodium_memcmp(expect, sig + 7, 6) != 0) return SignatureVerdict::kBadSignature;
  std::uint64_t ts = 0;
  for (int i = 5; i >= 0; --i) ts = (ts << 8) | sig[1 + i];
  const std::uint8_t sysid = frame[5], compid = frame[6], link = sig[0];
  Stream* s = nullptr;
  for (int i = 0; i < n_streams_; ++i) {
    Stream& k = streams_[static_cast<std::size_t>(i)];
    if (k.sysid == sysid && k.compid == compid && k.link == link) s = &k;
  }
  if (s != nullptr) {
    if (ts <= s->last) return SignatureVerdict::kReplay;
  } else {
    if (ts + kNewStreamLimit < newest_) return SignatureVerdict::kOld;
    if (n_streams_ == kMaxStreams) return SignatureVerdict::kStreamsFull;
    s = &streams_[static_cast<std::size_t>(n_streams_++)];
    s->sysid = sysid;
    s->compid = compid;
    s->link = link;
  }
  s->last = ts;
  if (ts > newest_) newest_ = ts;
  return SignatureVerdict::kOk;
}

}  // namespace tiller::mavlink
