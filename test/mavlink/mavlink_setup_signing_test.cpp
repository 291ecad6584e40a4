// tiller-mavlink's SETUP_SIGNING (mavlink_setup_signing.cpp): a new secret and initial timestamp
// taken only over the signed link from the station in control; unsigned (signing required:
// dropped and counted; not required: refused), another station's and an all-zero key refused;
// after it the old secret is refused and the new one obeyed; the key sink gets the secret.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <tiller/arm_request_t.hpp>

#include "auth/key.hpp"
#include "mavlink_rig.hpp"
#include "runtime/channels.hpp"

namespace tiller::mavlink {
namespace {

Secret new_key() {
  Secret k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(0xA0 + i);
  return k;
}

std::vector<std::uint8_t> setup(Station& st, const Secret& key, std::uint64_t ts, TimeUs now) {
  mavlink_message_t m;
  mavlink_msg_setup_signing_pack_status(st.w.sysid(), st.w.compid(), st.w.status(), &m, 1, 1,
                                        key.data(), ts);
  return st.frame(m, now);
}

std::size_t arms(const Rig& rig) {
  return rig.bus.on<arm_request_t>(channels::kArmRequest).size();
}

TEST(MavlinkSetupSigning, TheStationInControlSetsANewKeyOverTheSignedLink) {
  Rig rig;
  Secret saved{};
  int saves = 0;
  rig.node->set_key_sink([&](const Secret& s) {
    saved = s;
    ++saves;
    return true;
  });
  Station gcs(test_key());
  TimeUs t = kT0;
  // Unsigned while signing is required: dropped and counted, nothing changes.
  Station plain(std::nullopt);
  rig.in(setup(plain, new_key(), 0, t), t);
  EXPECT_EQ(rig.node->counter_value("rejected.frame.unsigned"), 1);
  // Another station, signed: refused.
  Station other(test_key(), 254);
  t += 1000;
  rig.in(setup(other, new_key(), 0, t), t);
  EXPECT_EQ(rig.node->counter_value("rejected.setup_signing"), 1);
  // An all-zero key (signing off): refused.
  t += 1000;
  rig.in(setup(gcs, Secret{}, 0, t), t);
  EXPECT_EQ(rig.node->counter_value("rejected.setup_signing"), 2);
  EXPECT_NE(rig.texts().find("all-zero key"), std::string::npos) << rig.texts();
  EXPECT_EQ(saves, 0);
  // The station in control, signed: taken, saved. Its initial timestamp 1 s past the clock's.
  const std::uint64_t initial = signing_timestamp(t) + 100000;
  t += 1000;
  rig.in(setup(gcs, new_key(), initial, t), t);
  EXPECT_EQ(rig.node->counter_value("signing.key_set"), 1);
  EXPECT_EQ(saves, 1);
  EXPECT_EQ(saved, new_key());
  EXPECT_NE(rig.texts().find("signing key set and saved"), std::string::npos) << rig.texts();
  // The vehicle's frames now verify with the new key, timestamps from the initial one on.
  const mavlink_message_t& last = rig.out.back();
  EXPECT_GE(std::uint64_t(last.signature[1]) | std::uint64_t(last.signature[2]) << 8 |
                std::uint64_t(last.signature[3]) << 16 | std::uint64_t(last.signature[4]) << 24 |
                std::uint64_t(last.signature[5]) << 32 | std::uint64_t(last.signature[6]) << 40,
            initial);
  std::vector<std::uint8_t> raw;
  rig.node->set_sink([&](const std::uint8_t* d, std::size_t n) { raw.assign(d, d + n); });
  rig.node->tick(t + 2000000);  // a heartbeat
  ASSERT_FALSE(raw.empty());
  EXPECT_EQ(SignatureChecker(new_key()).check(raw.data(), raw.size(), t), SignatureVerdict::kOk);
  EXPECT_EQ(SignatureChecker(test_key()).check(raw.data(), raw.size(), t),
            SignatureVerdict::kBadSignature);
  // The old key: refused. The new one (its timestamps past the initial): obeyed.
  const std::int64_t bad = rig.node->counter_value("rejected.frame.signature");
  t += 1000;
  rig.in(gcs.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, t), t);
  EXPECT_EQ(rig.node->counter_value("rejected.frame.signature"), bad + 1);
  EXPECT_EQ(arms(rig), 0u);
  Station gcs2(new_key());
  // Stamped before the initial timestamp less the minute a new stream may lag: refused as old.
  t += 1000;
  const TimeUs stale = kSigningEpochUs + static_cast<TimeUs>(initial - kNewStreamLimit - 10) * 10;
  rig.in(gcs2.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, stale), t);
  EXPECT_EQ(arms(rig), 0u);
  t += 1000;
  const TimeUs after = kSigningEpochUs + static_cast<TimeUs>(initial + 10) * 10;
  rig.in(gcs2.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, after), t);
  EXPECT_EQ(arms(rig), 1u);
}

TEST(MavlinkSetupSigning, UnsignedIsRefusedWhenSigningIsNotRequired) {
  Rig rig(false);
  Station plain(std::nullopt);
  rig.in(setup(plain, new_key(), 0, kT0), kT0);
  EXPECT_EQ(rig.node->counter_value("rejected.setup_signing"), 1);
  EXPECT_EQ(rig.node->counter_value("signing.key_set"), 0);
  EXPECT_NE(rig.texts().find("setup signing refused: not over a signed link"), std::string::npos)
      << rig.texts();
  // The old key still signs the vehicle's frames: a station with it verifies them.
  Station gcs(test_key());
  rig.in(gcs.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0 + 1000), kT0 + 1000);
  EXPECT_EQ(arms(rig), 1u);
}

TEST(MavlinkSetupSigning, TheKeyFileConfigSavesTheNewSecret) {
  // signing.key_file: the file is named in the params for apps/mavlink's key sink.
  const std::string dir = ::testing::TempDir() + "mavlink_setup_signing";
  std::filesystem::create_directories(dir);
  const std::string file = dir + "/gcs.key";
  auth::write_key_file(file, auth::generate_key(), true);
  const auto root = config::Value::parse("signing: {key_file: gcs.key}\n", dir + "/m.yaml");
  const MavlinkConfig c = load_mavlink(root, dir);
  EXPECT_EQ(c.node.secret_file, file);
  auth::Key k;
  k.bytes = new_key();
  k.id = auth::key_id(k.bytes);
  auth::write_key_file(file, k, true);  // what the sink does
  EXPECT_EQ(auth::load_key_file(file).bytes, new_key());
}

}  // namespace
}  // namespace tiller::mavlink
