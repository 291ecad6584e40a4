// tiller-mavlink's frames and node: frames byte for byte against node-mavlink's encoding (the
// hex below was printed by node-mavlink 2.3.0, test/mavlink/gcs), signatures, and the node's rules
// (signed commands only, one station, a centred stick first, parameter bounds, the mission
// protocol, malformed input).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "mavlink/frame.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mavlink/mavlink_node.hpp"
#include "mavlink_rig.hpp"
#include "runtime/channels.hpp"

namespace tiller::mavlink {
namespace {

mavlink_message_t heartbeat(FrameWriter& w) {
  mavlink_message_t m;
  mavlink_msg_heartbeat_pack_status(w.sysid(), w.compid(), w.status(), &m, MAV_TYPE_SURFACE_BOAT,
                                    MAV_AUTOPILOT_GENERIC, 0xc1, 2, MAV_STATE_STANDBY);
  return m;
}

TEST(MavlinkFrame, HeartbeatBytesMatchNodeMavlink) {
  FrameWriter w(1, 1, std::nullopt);
  w.status()->current_tx_seq = 7;
  mavlink_message_t m = heartbeat(w);
  std::uint8_t out[kMaxFrame];
  const std::size_t n = w.finish(m, kT0, out);
  // fd 09 00 00 | seq 07 | sys 01 comp 01 | id 000000 | custom 02000000 type 0b ap 00 base c1
  // status 03 version 03 | CRC 9fae (X.25 with HEARTBEAT's CRC_EXTRA 50, from the XML)
  EXPECT_EQ(hex(out, n), "fd090000070101000000020000000b00c103039fae");
}

TEST(MavlinkFrame, SignedHeartbeatMatchesNodeMavlink) {
  FrameWriter w(1, 1, test_key(), 5);
  w.status()->current_tx_seq = 7;
  mavlink_message_t m = heartbeat(w);
  std::uint8_t out[kMaxFrame];
  const std::size_t n = w.finish(m, kT0, out);
  // incompat flag 01, the CRC over the new header, link 05, timestamp (10 us since 2015)
  // 0x19759e6fe000 little-endian, SHA-256's first 6 bytes f0df0eb57429.
  EXPECT_EQ(hex(out, n), "fd090100070101000000020000000b00c1030378560500e06f9e7519f0df0eb57429");
  SignatureChecker c(test_key());
  EXPECT_EQ(c.check(out, n, kT0), SignatureVerdict::kOk);
  EXPECT_EQ(c.check(out, n, kT0), SignatureVerdict::kReplay);  // the same timestamp again
  out[12] ^= 1;                                                // a payload byte
  SignatureChecker c2(test_key());
  EXPECT_EQ(c2.check(out, n, kT0), SignatureVerdict::kBadSignature);
}

TEST(MavlinkFrame, ReaderTakesNodeMavlinksManualControl) {
  // MANUAL_CONTROL from sys 255 comp 190: x 500, y 0, z 500, r -250, target 1 (node-mavlink).
  const char* h = "fd0b000003ffbe450000f4010000f40106ff00000112c8";
  std::vector<std::uint8_t> b;
  for (const char* p = h; *p; p += 2)
    b.push_back(static_cast<std::uint8_t>(std::stoi(std::string(p, 2), nullptr, 16)));
  FrameReader r;
  int frames = 0;
  for (std::uint8_t c : b) {
    if (!r.feed(c)) continue;
    ++frames;
    ASSERT_EQ(r.frame().verdict, FrameVerdict::kOk);
    mavlink_manual_control_t mc;
    mavlink_msg_manual_control_decode(r.frame().msg, &mc);
    EXPECT_EQ(mc.x, 500);
    EXPECT_EQ(mc.z, 500);
    EXPECT_EQ(mc.r, -250);
    EXPECT_EQ(mc.target, 1);
    EXPECT_EQ(r.frame().n, b.size());
  }
  EXPECT_EQ(frames, 1);
}

// ---------------------------------------------------------------- the node

TEST(MavlinkNode, SendsTheHeartbeatOfASurfaceBoat) {
  Rig rig;
  rig.node->tick(kT0);
  ASSERT_GE(rig.count(MAVLINK_MSG_ID_HEARTBEAT), 1);
  for (const auto& m : rig.out) {
    if (m.msgid != MAVLINK_MSG_ID_HEARTBEAT) continue;
    EXPECT_EQ(mavlink_msg_heartbeat_get_type(&m), MAV_TYPE_SURFACE_BOAT);
    EXPECT_EQ(mavlink_msg_heartbeat_get_autopilot(&m), MAV_AUTOPILOT_GENERIC);
    EXPECT_EQ(mavlink_msg_heartbeat_get_base_mode(&m) & MAV_MODE_FLAG_SAFETY_ARMED, 0);
    EXPECT_TRUE(m.incompat_flags & MAVLINK_IFLAG_SIGNED);
  }
}

TEST(MavlinkNode, ASignedArmBecomesAnArmRequestAndAnUnsignedOneIsDropped) {
  Rig rig;
  Station unsigned_gcs(std::nullopt), gcs(test_key());
  rig.in(unsigned_gcs.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0), kT0);
  EXPECT_TRUE(rig.bus.on<arm_request_t>(channels::kArmRequest).empty());
  EXPECT_EQ(rig.node->counter_value("rejected.frame.unsigned"), 1);
  rig.in(gcs.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0 + 1000), kT0 + 1000);
  const auto arms = rig.bus.on<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(arms.size(), 1u);
  EXPECT_TRUE(arms[0].arm);
  EXPECT_EQ(arms[0].station, "qgc");
  EXPECT_EQ(rig.count(MAVLINK_MSG_ID_COMMAND_ACK), 1);
  // A replay of the same signed frame is refused.
  const auto f = gcs.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0 + 2000);
  rig.in(f, kT0 + 2000);
  rig.in(f, kT0 + 3000);
  EXPECT_EQ(rig.node->counter_value("rejected.frame.replay"), 1);
  // Wrongly keyed.
  Secret other = test_key();
  other[0] ^= 0xff;
  Station thief(other);
  rig.in(thief.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0 + 4000), kT0 + 4000);
  EXPECT_EQ(rig.node->counter_value("rejected.frame.signature"), 1);
  EXPECT_EQ(rig.bus.on<arm_request_t>(channels::kArmRequest).size(), 2u);
}

TEST(MavlinkNode, ASecondStationIsRefused) {
  Rig rig;
  Station second(test_key(), 254);
  rig.in(second.command(MAV_CMD_COMPONENT_ARM_DISARM, 1, 0, kT0), kT0);
  rig.in(second.manual(0, 0, kT0 + 1000), kT0 + 1000);
  EXPECT_TRUE(rig.bus.on<arm_request_t>(channels::kArmRequest).empty());
  EXPECT_TRUE(rig.bus.on<manual_demand_t>(channels::kManualDemand).empty());
  EXPECT_EQ(rig.node->counter_value("rejected.frame.other_station"), 2);
  EXPECT_NE(rig.texts().find("station 254 is not in control"), std::string::npos);
  ASSERT_EQ(rig.count(MAVLINK_MSG_ID_COMMAND_ACK), 1);
  for (const auto& m : rig.out) {
    if (m.msgid == MAVLINK_MSG_ID_COMMAND_ACK) {
      EXPECT_EQ(mavlink_msg_command_ack_get_result(&m), MAV_RESULT_DENIED);
    }
  }
}

TEST(MavlinkNode, ManualControlNeedsACentredStickAndTimesOut) {
  Rig rig;
  Station gcs(test_key());
  rig.in(gcs.manual(800, 0, kT0), kT0);  // held at start: neutral, invalid
  auto d = rig.bus.on<manual_demand_t>(channels::kManualDemand);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_FALSE(d[0].valid);
  rig.in(gcs.manual(0, 0, kT0 + 40000), kT0 + 40000);  // centred
  rig.in(gcs.manual(500, -1000, kT0 + 80000), kT0 + 80000);
  d = rig.bus.on<manual_demand_t>(channels::kManualDemand);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_TRUE(d[2].valid);
  EXPECT_NEAR(d[2].demand[0], (0.5 - 0.05) / 0.95, 1e-9);  // teleop's deadzone shaping
  EXPECT_NEAR(d[2].demand[5], -1.0, 1e-9);
  EXPECT_EQ(d[2].station, "qgc");
  rig.node->tick(kT0 + 80000 + 600000);  // silent past MAN_TIMEOUT (0.5 s)
  d = rig.bus.on<manual_demand_t>(channels::kManualDemand);
  EXPECT_FALSE(d.back().valid);
  EXPECT_EQ(d.back().demand[0], 0.0);
  EXPECT_FALSE(rig.node->pilot_centred());
}

TEST(MavlinkNode, AParameterSetOutOfBoundsIsRefused) {
  Rig rig;
  Station gcs(test_key());
  mavlink_message_t m;
  mavlink_msg_param_request_list_pack_status(255, 190, gcs.w.status(), &m, 1, 1);
  rig.in(gcs.frame(m, kT0), kT0);
  EXPECT_EQ(rig.count(MAVLINK_MSG_ID_PARAM_VALUE), static_cast<int>(kParamCount));
  char id[16] = "MAN_GAIN";
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, id, 1.5f,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 1000), kT0 + 1000);
  EXPECT_EQ(rig.node->param(kManGain), 1.0);
  EXPECT_NE(rig.texts().find("MAN_GAIN refused: 1.5 outside [0, 1]"), std::string::npos);
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, id, 0.5f,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 2000), kT0 + 2000);
  EXPECT_EQ(rig.node->param(kManGain), 0.5);
}

TEST(MavlinkNode, AFiveItemMissionUploadsAndDownloads) {
  Rig rig;
  Station gcs(test_key());
  mavlink_message_t m;
  TimeUs t = kT0;
  mavlink_msg_mission_count_pack_status(255, 190, gcs.w.status(), &m, 1, 1, 5,
                                        MAV_MISSION_TYPE_MISSION, 0);
  rig.in(gcs.frame(m, t), t);
  for (int seq = 0; seq < 5; ++seq) {
    ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_REQUEST_INT) << seq;
    EXPECT_EQ(mavlink_msg_mission_request_int_get_seq(&rig.out.back()), seq);
    t += 1000;
    mavlink_msg_mission_item_int_pack_status(
        255, 190, gcs.w.status(), &m, 1, 1, static_cast<std::uint16_t>(seq),
        MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, MAV_CMD_NAV_WAYPOINT, 0, 1, 0, 0, 0, 0,
        473977000 + seq * 1000, 85455000, 0, MAV_MISSION_TYPE_MISSION);
    rig.in(gcs.frame(m, t), t);
  }
  ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_ACK);
  EXPECT_EQ(mavlink_msg_mission_ack_get_type(&rig.out.back()), MAV_MISSION_ACCEPTED);
  ASSERT_EQ(rig.node->mission(MAV_MISSION_TYPE_MISSION).size(), 5u);
  mavlink_msg_mission_request_list_pack_status(255, 190, gcs.w.status(), &m, 1, 1,
                                               MAV_MISSION_TYPE_MISSION);
  t += 1000;
  rig.in(gcs.frame(m, t), t);
  ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_COUNT);
  EXPECT_EQ(mavlink_msg_mission_count_get_count(&rig.out.back()), 5);
  mavlink_msg_mission_request_int_pack_status(255, 190, gcs.w.status(), &m, 1, 1, 3,
                                              MAV_MISSION_TYPE_MISSION);
  t += 1000;
  rig.in(gcs.frame(m, t), t);
  ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_ITEM_INT);
  EXPECT_EQ(mavlink_msg_mission_item_int_get_x(&rig.out.back()), 473980000);
}

TEST(MavlinkNode, AMissionThePlanSupportRefusesIsRefused) {
  Rig rig;
  Station gcs(test_key());
  mavlink_message_t m;
  mavlink_msg_mission_count_pack_status(255, 190, gcs.w.status(), &m, 1, 1, 1,
                                        MAV_MISSION_TYPE_MISSION, 0);
  rig.in(gcs.frame(m, kT0), kT0);
  mavlink_msg_mission_item_int_pack_status(
      255, 190, gcs.w.status(), &m, 1, 1, 0, MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, MAV_CMD_NAV_TAKEOFF,
      0, 1, 0, 0, 0, 0, 473977000, 85455000, 10, MAV_MISSION_TYPE_MISSION);
  rig.in(gcs.frame(m, kT0 + 1000), kT0 + 1000);
  ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_ACK);
  EXPECT_EQ(mavlink_msg_mission_ack_get_type(&rig.out.back()), MAV_MISSION_UNSUPPORTED);
  EXPECT_TRUE(rig.node->mission(MAV_MISSION_TYPE_MISSION).empty());
  EXPECT_NE(rig.texts().find("item 0"), std::string::npos) << rig.texts();
}

TEST(MavlinkNode, MalformedFramesAreCountedAndNothingMoves) {
  Rig rig(false);  // even with unsigned frames accepted
  Station gcs(std::nullopt);
  std::mt19937 rng(7);
  std::vector<std::uint8_t> good = gcs.manual(900, 900, kT0);
  for (int i = 0; i < 20000; ++i) {
    std::vector<std::uint8_t> f = good;
    if (i % 2) {  // a flipped byte (any of them, the CRC included)
      f[rng() % f.size()] ^= static_cast<std::uint8_t>(1 + rng() % 255);
    } else {  // random bytes, magic first
      f.assign(1 + rng() % 300, 0);
      for (auto& b : f) b = static_cast<std::uint8_t>(rng());
      f[0] = 0xfd;
    }
    rig.in(f, kT0 + i);
  }
  for (const auto& d : rig.bus.on<manual_demand_t>(channels::kManualDemand)) {
    EXPECT_FALSE(d.valid);
    for (double v : d.demand) EXPECT_EQ(v, 0.0);
  }
  EXPECT_TRUE(rig.bus.on<arm_request_t>(channels::kArmRequest).empty());
  EXPECT_GT(rig.node->counter_value("rejected.frame.crc"), 9000);
}

}  // namespace
}  // namespace tiller::mavlink

namespace tiller::mavlink {
namespace {

// serial.baud: a speed the serial link cannot open is a config error naming the key, not a
// failure when the port opens (the loader took 1200 ... 921600 before).
TEST(MavlinkConfig, SerialBaudIsOneOfTheStandardSpeeds) {
  const auto load = [](const std::string& baud) {
    return load_mavlink(
        config::Value::parse("serial: {device: /dev/ttyUSB0, baud: " + baud + "}", "radio.yaml"),
        ".");
  };
  EXPECT_EQ(load("115200").transport.serial_baud, 115200);
  for (const char* bad : {"1200", "56000", "1000000"}) {
    try {
      load(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const config::Error& e) {
      EXPECT_NE(std::string(e.what()).find("baud"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("radio.yaml"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace tiller::mavlink

namespace tiller::mavlink {
namespace {

// The serial link's whole-frame drops reach the heartbeat's counters.
TEST(MavlinkNode, TheLinksDroppedFramesAreACounter) {
  MavlinkNode node(
      load_mavlink_file(std::string(TILLER_SOURCE_DIR) + "/config/mavlink/usv_radio.yaml").node);
  EXPECT_EQ(node.counter_value("link.frames_dropped"), 0);
  node.set_link_frames_dropped(3);
  node.set_link_frames_dropped(7);  // the link's running total, not an increment
  EXPECT_EQ(node.counter_value("link.frames_dropped"), 7);
}

}  // namespace
}  // namespace tiller::mavlink
