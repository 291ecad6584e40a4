// A per-vehicle signing key: 32 random bytes (libsodium's crypto_generichash_KEYBYTES), shared
// by every process of one vehicle (and its topside computer), kept in a key file that only its
// owner may read (mode 0600). The key id is a 32-bit public name of the key (a keyed hash of a
// fixed text, so it says nothing about the key) carried in every trailer, so a process with
// another vehicle's key, or a key that was rotated, shows as "wrong_key" instead of "bad_mac".
//
// Key file format (text, written by tiller-key):
//   # comment lines start with '#'
//   <64 lowercase or uppercase hexadecimal digits>
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace tiller::auth {

inline constexpr std::size_t kKeyBytes = 32;

struct Key {
  std::array<std::uint8_t, kKeyBytes> bytes{};
  std::uint32_t id = 0;  // key_id(bytes)
};

// The public id of a key (first 4 bytes of BLAKE2b keyed with it over "tiller key id v1").
std::uint32_t key_id(const std::array<std::uint8_t, kKeyBytes>& bytes);

// A new key from libsodium's randombytes_buf (the system's CSPRNG).
Key generate_key();

// A random boot nonce in [1, 2^63): drawn once per start of a process (tiller-esc's
// arm_state_t.boot_nonce), so a command captured before a restart names another boot.
std::int64_t random_nonce();

// Parses a key file's text; throws std::runtime_error "key file 'PATH': ..." when it is not one.
Key parse_key(const std::string& text, const std::string& path);

// Loads and checks a key file. Throws std::runtime_error naming the file when it is missing,
// not a regular file, readable or writable by group or others (mode & 077), or malformed.
Key load_key_file(const std::string& path);

// Writes `key` to a new file with mode 0600 (atomically: a temporary file linked into place, so
// a concurrent reader never sees half a key). Throws std::runtime_error naming the file if it
// exists (unless overwrite) or cannot be written.
void write_key_file(const std::string& path, const Key& key, bool overwrite);

// The key id as 8 hexadecimal digits (what tiller-key prints and the docs call the key id).
std::string key_id_hex(std::uint32_t id);

}  // namespace tiller::auth
