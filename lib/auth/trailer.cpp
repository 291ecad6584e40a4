#include "auth/trailer.hpp"

#include <sodium.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace tiller::auth {

namespace {
constexpr int kSenderAt = 0;
constexpr int kTimeAt = 16;
constexpr int kKeyIdAt = 24;
constexpr int kMacAt = 28;
constexpr int kMagicAt = 44;
static_assert(kMagicAt + 4 == kTrailerSize);
static_assert(kMacAt + kMacBytes == kMagicAt);

void put_be(std::uint8_t* p, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) {
    p[i] = static_cast<std::uint8_t>(v & 0xff);
    v >>= 8;
  }
}
std::uint64_t get_be(const std::uint8_t* p, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}
}  // namespace

bool has_trailer(const std::uint8_t* data, int size) {
  return data != nullptr && size >= kTrailerSize &&
         std::memcmp(data + size - 4, kMagic, sizeof kMagic) == 0;
}

int payload_size(const std::uint8_t* data, int size) {
  return has_trailer(data, size) ? size - kTrailerSize : size;
}

TrailerFields read_trailer(const std::uint8_t* t) {
  TrailerFields f;
  const char* s = reinterpret_cast<const char*>(t + kSenderAt);
  f.sender =
      std::string_view(s, static_cast<std::size_t>(std::find(s, s + kSenderBytes, '\0') - s));
  f.time_us = static_cast<TimeUs>(get_be(t + kTimeAt, 8));
  f.key_id = static_cast<std::uint32_t>(get_be(t + kKeyIdAt, 4));
  return f;
}

bool valid_sender(std::string_view sender) {
  if (sender.empty() || sender.size() > static_cast<std::size_t>(kSenderBytes)) return false;
  return std::all_of(sender.begin(), sender.end(), [](char c) { return c > 0x20 && c < 0x7f; });
}

void compute_mac(const Key& key, std::string_view channel, const std::uint8_t* payload, int size,
                 const std::uint8_t* trailer_head, std::uint8_t* mac) {
  crypto_generichash_state st;
  crypto_generichash_init(&st, key.bytes.data(), key.bytes.size(), kMacBytes);
  std::uint8_t len[4];
  crypto_generichash_update(&st, kMagic, sizeof kMagic);
  put_be(len, channel.size(), 4);
  crypto_generichash_update(&st, len, sizeof len);
  crypto_generichash_update(&st, reinterpret_cast<const unsigned char*>(channel.data()),
                            channel.size());
  put_be(len, static_cast<std::uint64_t>(size), 4);
  crypto_generichash_update(&st, len, sizeof len);
  crypto_generichash_update(&st, payload, static_cast<unsigned long long>(size));
  crypto_generichash_update(&st, trailer_head, kMacAt);
  crypto_generichash_final(&st, mac, kMacBytes);
  sodium_memzero(&st, sizeof st);
}

Signer::Signer(const Key& key, std::string_view sender) : key_(key) {
  if (!valid_sender(sender)) {
    throw std::invalid_argument("signing sender name '" + std::string(sender) +
                                "' must be 1 to 16 printable ASCII characters");
  }
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  std::memcpy(sender_, sender.data(), sender.size());
}

TimeUs Signer::sign(std::string_view channel, const std::uint8_t* payload, int size, TimeUs now,
                    std::uint8_t* out) {
  last_ = std::max(now, last_ + 1);
  std::memcpy(out + kSenderAt, sender_, kSenderBytes);
  put_be(out + kTimeAt, static_cast<std::uint64_t>(last_), 8);
  put_be(out + kKeyIdAt, key_.id, 4);
  compute_mac(key_, channel, payload, size, out, out + kMacAt);
  std::memcpy(out + kMagicAt, kMagic, sizeof kMagic);
  return last_;
}

}  // namespace tiller::auth
