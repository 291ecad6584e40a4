#include "auth/key.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace tiller::auth {

namespace {
void init_sodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("key file '" + path + "': " + what);
}

std::string mode_text(mode_t m) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%04o", static_cast<unsigned>(m & 07777));
  return buf;
}
}  // namespace

std::uint32_t key_id(const std::array<std::uint8_t, kKeyBytes>& bytes) {
  static constexpr char kLabel[] = "tiller key id v1";
  std::uint8_t h[16];
  crypto_generichash(h, sizeof h, reinterpret_cast<const unsigned char*>(kLabel), sizeof kLabel - 1,
                     bytes.data(), bytes.size());
  return (std::uint32_t{h[0]} << 24) | (std::uint32_t{h[1]} << 16) | (std::uint32_t{h[2]} << 8) |
         std::uint32_t{h[3]};
}

std::int64_t random_nonce() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium failed to initialise");
  std::uint64_t v = 0;
  while (v == 0) {
    randombytes_buf(&v, sizeof v);
    v >>= 1;  // [0, 2^63): positive as an int64
  }
  return static_cast<std::int64_t>(v);
}

Key generate_key() {
  init_sodium();
  Key k;
  randombytes_buf(k.bytes.data(), k.bytes.size());
  k.id = key_id(k.bytes);
  return k;
}

Key parse_key(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line, hex;
  int n_lines = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t");
    hex = line.substr(first, last - first + 1);
    ++n_lines;
  }
  if (n_lines != 1) {
    fail(path, "malformed: expected one line of " + std::to_string(2 * kKeyBytes) +
                   " hexadecimal digits (make one with tiller-key new FILE), found " +
                   std::to_string(n_lines) + " key lines");
  }
  Key k;
  std::size_t n = 0;
  const char* end = nullptr;
  if (hex.size() != 2 * kKeyBytes ||
      sodium_hex2bin(k.bytes.data(), k.bytes.size(), hex.data(), hex.size(), nullptr, &n, &end) !=
          0 ||
      n != kKeyBytes || end != hex.data() + hex.size()) {
    fail(path, "malformed: expected " + std::to_string(2 * kKeyBytes) +
                   " hexadecimal digits (32 bytes), got " + std::to_string(hex.size()) +
                   " characters (make one with tiller-key new FILE)");
  }
  init_sodium();
  k.id = key_id(k.bytes);
  return k;
}

Key load_key_file(const std::string& path) {
  if (path.empty()) throw std::runtime_error("key file: no path given");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    fail(path, std::strerror(errno) +
                   std::string(" (make one with tiller-key new FILE; see docs/safety.md)"));
  }
  if (!S_ISREG(st.st_mode)) fail(path, "not a regular file");
  if ((st.st_mode & 077) != 0) {
    fail(path, "readable or writable by group or others (mode " + mode_text(st.st_mode) +
                   "); a signing key must be private to its owner: chmod 600 " + path);
  }
  std::ifstream f(path);
  if (!f) fail(path, "cannot be read");
  std::stringstream s;
  s << f.rdbuf();
  return parse_key(s.str(), path);
}

void write_key_file(const std::string& path, const Key& key, bool overwrite) {
  char hex[2 * kKeyBytes + 1];
  sodium_bin2hex(hex, sizeof hex, key.bytes.data(), key.bytes.size());
  const std::string text = "# Tiller signing key (tiller-key), id " + key_id_hex(key.id) +
                           ". Secret: keep mode 0600, never in git or a log.\n" + hex + "\n";
  sodium_memzero(hex, sizeof hex);
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
  if (fd < 0) fail(path, std::string("cannot create: ") + std::strerror(errno));
  // The umask cannot widen 0600, but fchmod makes the mode exact whatever it is.
  bool ok = ::fchmod(fd, 0600) == 0 &&
            ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
            ::fsync(fd) == 0;
  const int err = errno;
  ::close(fd);
  if (!ok) {
    ::unlink(tmp.c_str());
    fail(path, std::string("cannot write: ") + std::strerror(err));
  }
  const int r = overwrite ? ::rename(tmp.c_str(), path.c_str()) : ::link(tmp.c_str(), path.c_str());
  const int link_err = errno;
  ::unlink(tmp.c_str());
  if (r != 0) {
    fail(path, link_err == EEXIST
                   ? std::string("exists already (tiller-key new --force replaces it)")
                   : std::string("cannot create: ") + std::strerror(link_err));
  }
}

std::string key_id_hex(std::uint32_t id) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", id);
  return buf;
}

}  // namespace tiller::auth
