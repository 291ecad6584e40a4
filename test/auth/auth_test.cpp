// lib/auth: a signed message verifies and gives back the exact payload and sender; changing
// any byte, the channel or the key is refused; the replay window's edges are exact; key files
// are checked for mode and format; signing and checking allocate nothing.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../common/alloc_count.hpp"
#include "auth/key.hpp"
#include "auth/trailer.hpp"
#include "auth/verifier.hpp"

namespace tiller::auth {
namespace {

constexpr TimeUs kT0 = 1'764'000'000'000'000;  // a 2025 time, us since the epoch
const std::string kChannel = "TILLER_THRUSTER_COMMAND";

Key fixed_key(std::uint8_t seed) {
  Key k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(seed + i);
  k.id = key_id(k.bytes);
  return k;
}

std::vector<std::uint8_t> payload(int n) {
  std::vector<std::uint8_t> p(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) p[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i * 7 + 3);
  return p;
}

std::vector<std::uint8_t> signed_packet(Signer& s, const std::vector<std::uint8_t>& p, TimeUs now,
                                        const std::string& channel = kChannel) {
  std::vector<std::uint8_t> out(p);
  out.resize(p.size() + kTrailerSize);
  s.sign(channel, p.data(), static_cast<int>(p.size()), now, out.data() + p.size());
  return out;
}

Policy keyed(const Key& k, bool require = true) {
  Policy p;
  p.key = k;
  p.require_signed = require;
  return p;
}

Checked check(Verifier& v, const std::vector<std::uint8_t>& pkt, TimeUs now,
              const std::string& channel = kChannel) {
  return v.check(channel, pkt.data(), static_cast<int>(pkt.size()), now);
}

TEST(Auth, RoundTripGivesPayloadAndSender) {
  const Key k = fixed_key(1);
  Signer s(k, "mixer");
  Verifier v(keyed(k));
  const auto p = payload(93);
  const auto pkt = signed_packet(s, p, kT0);
  ASSERT_EQ(pkt.size(), p.size() + 48);
  EXPECT_TRUE(has_trailer(pkt.data(), static_cast<int>(pkt.size())));
  EXPECT_EQ(payload_size(pkt.data(), static_cast<int>(pkt.size())), 93);
  const Checked c = check(v, pkt, kT0 + 300);
  EXPECT_EQ(c.verdict, Verdict::kSigned);
  EXPECT_EQ(c.payload_size, 93);
  EXPECT_EQ(c.sender, "mixer");
  EXPECT_EQ(c.stamp, kT0);
  EXPECT_EQ(std::memcmp(pkt.data(), p.data(), p.size()), 0);  // the payload is untouched
  const TrailerFields f = read_trailer(pkt.data() + p.size());
  EXPECT_EQ(f.sender, "mixer");
  EXPECT_EQ(f.time_us, kT0);
  EXPECT_EQ(f.key_id, k.id);
  // The layout: sender NUL-padded at 0, stamp big-endian at 16, magic at 44.
  const std::uint8_t* t = pkt.data() + p.size();
  EXPECT_EQ(std::memcmp(t, "mixer\0\0\0\0\0\0\0\0\0\0\0", 16), 0);
  EXPECT_EQ(t[23], static_cast<std::uint8_t>(kT0 & 0xff));
  EXPECT_EQ(t[16], static_cast<std::uint8_t>((kT0 >> 56) & 0xff));
  EXPECT_EQ(std::memcmp(t + 44, kMagic, 4), 0);
}

TEST(Auth, EmptyPayloadAndSixteenCharacterSender) {
  const Key k = fixed_key(2);
  Signer s(k, "abcdefghijklmnop");
  Verifier v(keyed(k));
  const auto pkt = signed_packet(s, {}, kT0);
  const Checked c = check(v, pkt, kT0);
  EXPECT_EQ(c.verdict, Verdict::kSigned);
  EXPECT_EQ(c.payload_size, 0);
  EXPECT_EQ(c.sender, "abcdefghijklmnop");
  EXPECT_THROW(Signer(k, "abcdefghijklmnopq"), std::invalid_argument);
  EXPECT_THROW(Signer(k, ""), std::invalid_argument);
  EXPECT_THROW(Signer(k, "has space"), std::invalid_argument);
}

// Every single-byte change of the packet is refused: in the payload, sender, stamp and MAC it
// is a bad MAC; in the key id a wrong key; in the magic the packet is no longer signed.
TEST(Auth, TamperingWithAnyByteIsRefused) {
  const Key k = fixed_key(3);
  Signer s(k, "teleop");
  const auto p = payload(40);
  const auto good = signed_packet(s, p, kT0);
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (std::uint8_t flip : {std::uint8_t{0x01}, std::uint8_t{0x80}}) {
      auto bad = good;
      bad[i] ^= flip;
      Verifier v(keyed(k));  // fresh: no replay state
      const Checked c = check(v, bad, kT0);
      const std::size_t at = i >= p.size() ? i - p.size() : SIZE_MAX;  // offset in the trailer
      Verdict want = Verdict::kBadMac;
      if (at != SIZE_MAX && at >= 24 && at < 28) want = Verdict::kWrongKey;
      if (at != SIZE_MAX && at >= 44) want = Verdict::kUnsigned;
      EXPECT_EQ(c.verdict, want) << "byte " << i << " (trailer offset " << at << ") ^ " << int(flip)
                                 << ": " << to_string(c.verdict);
    }
  }
  Verifier v(keyed(k));
  EXPECT_EQ(check(v, good, kT0).verdict, Verdict::kSigned);  // the original still verifies
}

TEST(Auth, AnotherChannelOrKeyIsRefused) {
  const Key k = fixed_key(4);
  Signer s(k, "teleop");
  const auto pkt = signed_packet(s, payload(30), kT0);
  Verifier v(keyed(k));
  EXPECT_EQ(check(v, pkt, kT0, "TILLER_ARM_REQUEST").verdict, Verdict::kBadMac);
  Verifier other(keyed(fixed_key(5)));
  EXPECT_EQ(check(other, pkt, kT0).verdict, Verdict::kWrongKey);
  // The same key id but other key bytes (a forger who copied the id): the MAC fails.
  Key forged = fixed_key(6);
  forged.id = k.id;
  Signer fs(forged, "teleop");
  EXPECT_EQ(check(v, signed_packet(fs, payload(30), kT0), kT0).verdict, Verdict::kBadMac);
}

TEST(Auth, UnsignedIsRefusedOnlyWhenRequired) {
  const Key k = fixed_key(7);
  const auto p = payload(20);
  Verifier strict(keyed(k, true));
  EXPECT_EQ(check(strict, p, kT0).verdict, Verdict::kUnsigned);
  Verifier lax(keyed(k, false));
  const Checked c = check(lax, p, kT0);
  EXPECT_EQ(c.verdict, Verdict::kUnsignedAccepted);
  EXPECT_EQ(c.payload_size, 20);
  EXPECT_TRUE(c.sender.empty());
  // A bad signature is refused even when signing is not required.
  Signer s(fixed_key(8), "x");
  EXPECT_EQ(check(lax, signed_packet(s, p, kT0), kT0).verdict, Verdict::kWrongKey);
  // Without a key nothing is checked; a trailer is stripped.
  Verifier none{Policy{}};
  const Checked n = check(none, signed_packet(s, p, kT0), kT0);
  EXPECT_EQ(n.verdict, Verdict::kUnsignedAccepted);
  EXPECT_EQ(n.payload_size, 20);
  Policy bad;
  bad.require_signed = true;
  EXPECT_THROW(Verifier{bad}, std::runtime_error);
}

TEST(Auth, ReplaysAreRefusedPerStream) {
  const Key k = fixed_key(9);
  Signer teleop(k, "teleop");
  Signer mission(k, "mission");
  Verifier v(keyed(k));
  const auto a1 = signed_packet(teleop, payload(10), kT0);
  const auto a2 = signed_packet(teleop, payload(10), kT0);  // same clock: stamp kT0 + 1
  EXPECT_EQ(read_trailer(a2.data() + 10).time_us, kT0 + 1);
  EXPECT_EQ(check(v, a1, kT0).verdict, Verdict::kSigned);
  EXPECT_EQ(check(v, a1, kT0).verdict, Verdict::kReplay);  // the same message again
  EXPECT_EQ(check(v, a2, kT0).verdict, Verdict::kSigned);
  EXPECT_EQ(check(v, a1, kT0).verdict, Verdict::kReplay);  // an older one
  // Another sender, and the same sender on another channel, are other streams.
  EXPECT_EQ(check(v, signed_packet(mission, payload(10), kT0 - 5), kT0).verdict, Verdict::kSigned);
  EXPECT_EQ(
      check(v, signed_packet(teleop, payload(10), kT0, "TILLER_MODE"), kT0, "TILLER_MODE").verdict,
      Verdict::kSigned);
  EXPECT_EQ(v.streams(), 3);
  // A clock that steps back does not make a sender's stamps go back.
  const auto a3 = signed_packet(teleop, payload(10), kT0 - 1'000'000);
  EXPECT_GT(read_trailer(a3.data() + 10).time_us, kT0);
  EXPECT_EQ(check(v, a3, kT0).verdict, Verdict::kSigned);
}

TEST(Auth, WindowEdgesAreExact) {
  const Key k = fixed_key(10);
  Policy pol = keyed(k);
  pol.window_us = 1'000'000;
  const TimeUs now = kT0 + 5'000'000;
  struct Case {
    TimeUs stamp;
    Verdict want;
  };
  for (const Case& cs :
       {Case{now - 1'000'000, Verdict::kSigned}, Case{now - 1'000'001, Verdict::kWindow},
        Case{now + 1'000'000, Verdict::kSigned}, Case{now + 1'000'001, Verdict::kWindow},
        Case{now, Verdict::kSigned}}) {
    Signer s(k, "teleop");
    Verifier v(pol);
    const auto pkt = signed_packet(s, payload(12), cs.stamp);
    EXPECT_EQ(check(v, pkt, now).verdict, cs.want) << "stamp - now = " << cs.stamp - now;
  }
  // A known stream's replay is named as a replay even when it is also outside the window.
  Signer s(k, "teleop");
  Verifier v(pol);
  const auto old = signed_packet(s, payload(12), now);
  EXPECT_EQ(check(v, old, now).verdict, Verdict::kSigned);
  EXPECT_EQ(check(v, old, now + 10'000'000).verdict, Verdict::kReplay);
  // A new receiver (a restarted process) refuses a capture older than the window.
  Verifier restarted(pol);
  EXPECT_EQ(check(restarted, old, now + 1'000'001).verdict, Verdict::kWindow);
}

TEST(Auth, StreamTableIsBounded) {
  const Key k = fixed_key(11);
  Verifier v(keyed(k));
  for (int i = 0; i < Verifier::kMaxStreams; ++i) {
    Signer s(k, "s" + std::to_string(i));
    ASSERT_EQ(check(v, signed_packet(s, payload(4), kT0), kT0).verdict, Verdict::kSigned) << i;
  }
  Signer extra(k, "extra");
  EXPECT_EQ(check(v, signed_packet(extra, payload(4), kT0), kT0).verdict, Verdict::kStreamsFull);
  Signer s0(k, "s0");  // a known stream still works
  EXPECT_EQ(check(v, signed_packet(s0, payload(4), kT0 + 1), kT0).verdict, Verdict::kSigned);
}

TEST(Auth, SignAndCheckAllocateNothing) {
  const Key k = fixed_key(12);
  Signer s(k, "mixer");
  Verifier v(keyed(k));
  const auto p = payload(120);
  std::vector<std::uint8_t> pkt(p.size() + kTrailerSize);
  std::memcpy(pkt.data(), p.data(), p.size());
  s.sign(kChannel, p.data(), 120, kT0, pkt.data() + 120);
  ASSERT_EQ(check(v, pkt, kT0).verdict, Verdict::kSigned);
  const long before = test::allocations();
  for (int i = 1; i <= 1000; ++i) {
    s.sign(kChannel, p.data(), 120, kT0 + i, pkt.data() + 120);
    if (v.check(kChannel, pkt.data(), static_cast<int>(pkt.size()), kT0 + i).verdict !=
        Verdict::kSigned)
      FAIL() << i;
  }
  EXPECT_EQ(test::allocations() - before, 0);
}

// ---- key files

struct TempDir {
  std::filesystem::path p =
      std::filesystem::temp_directory_path() / ("tiller_auth_test_" + std::to_string(::getpid()));
  TempDir() { std::filesystem::create_directories(p); }
  ~TempDir() { std::filesystem::remove_all(p); }
  std::string file(const std::string& n) const { return (p / n).string(); }
};

std::string error_of(const std::string& path) {
  try {
    load_key_file(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(AuthKeyFile, NewKeyIsPrivateAndLoadsBack) {
  TempDir d;
  const std::string f = d.file("vehicle.key");
  const Key k = generate_key();
  write_key_file(f, k, false);
  struct stat st {};
  ASSERT_EQ(::stat(f.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const Key back = load_key_file(f);
  EXPECT_EQ(back.bytes, k.bytes);
  EXPECT_EQ(back.id, k.id);
  EXPECT_EQ(key_id_hex(k.id).size(), 8u);
  // Not over an existing file, unless asked.
  EXPECT_THROW(write_key_file(f, generate_key(), false), std::runtime_error);
  const Key k2 = generate_key();
  EXPECT_NE(k2.bytes, k.bytes);
  write_key_file(f, k2, true);
  EXPECT_EQ(load_key_file(f).bytes, k2.bytes);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(d.p), {}), 1);  // no temp left
}

TEST(AuthKeyFile, GroupOrWorldAccessIsRefusedNamingTheFile) {
  TempDir d;
  const std::string f = d.file("k.key");
  write_key_file(f, generate_key(), false);
  for (mode_t m : {0640, 0604, 0620, 0602, 0644, 0660}) {
    ASSERT_EQ(::chmod(f.c_str(), m), 0);
    const std::string e = error_of(f);
    EXPECT_NE(e.find("key file '" + f + "'"), std::string::npos) << e;
    EXPECT_NE(e.find("group or others"), std::string::npos) << e;
    EXPECT_NE(e.find("chmod 600"), std::string::npos) << e;
  }
  ASSERT_EQ(::chmod(f.c_str(), 0400), 0);
  EXPECT_EQ(error_of(f), "");
}

TEST(AuthKeyFile, MissingOrMalformedIsRefusedNamingTheFile) {
  TempDir d;
  const std::string missing = d.file("nope.key");
  EXPECT_NE(error_of(missing).find("key file '" + missing + "': No such file"), std::string::npos)
      << error_of(missing);
  EXPECT_NE(error_of(d.p.string()).find("not a regular file"), std::string::npos);
  const std::string hex64(64, 'a');
  struct Bad {
    const char* name;
    std::string text;
  };
  for (const Bad& b :
       {Bad{"empty", ""}, Bad{"short", std::string(62, 'a') + "\n"},
        Bad{"long", std::string(66, 'a') + "\n"}, Bad{"nonhex", std::string(63, 'a') + "g\n"},
        Bad{"two", hex64 + "\n" + hex64 + "\n"}, Bad{"comment_only", "# only a comment\n"}}) {
    const std::string f = d.file(std::string(b.name) + ".key");
    { std::ofstream(f) << b.text; }
    ::chmod(f.c_str(), 0600);
    const std::string e = error_of(f);
    EXPECT_NE(e.find("key file '" + f + "': malformed"), std::string::npos) << b.name << ": " << e;
  }
  // Comments, blank lines, surrounding blanks and CRLF are fine.
  const std::string ok = d.file("ok.key");
  { std::ofstream(ok) << "# a comment\n\n  " << std::string(64, 'F') << "  \r\n"; }
  ::chmod(ok.c_str(), 0600);
  EXPECT_EQ(error_of(ok), "");
  EXPECT_EQ(load_key_file(ok).bytes[0], 0xff);
}

}  // namespace
}  // namespace tiller::auth
