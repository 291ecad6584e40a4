// tiller-mavlink flying an uploaded mission beyond plain waypoints (mavlink_fly.cpp): a speed
// change, a jump with a repeat count and a loiter time, uploaded over the mission protocol, built
// into the one mission model and flown leg by leg by mission::Sequencer; downloaded the same; a
// command the .plan support does not know refused with MAV_MISSION_UNSUPPORTED and a STATUSTEXT.
// Figures by hand: about the datum (47.3977 N, 8.5455 E), 0.0001 deg of latitude is 11.13 m north
// and 0.0001 deg of longitude 7.53 m east (cos 47.3977 deg * 111.32 km / deg: within 0.1 m).
#include <gtest/gtest.h>

#include <tiller/datum_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>

#include "mavlink_rig.hpp"
#include "runtime/channels.hpp"

namespace tiller::mavlink {
namespace {

template <class Msg>
void lcm_in(Rig& rig, const char* channel, const Msg& m, TimeUs now) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  rig.node->deliver(channel, b.data(), static_cast<int>(b.size()), now);
}

struct Item {
  std::uint16_t cmd;
  float p1, p2;
  std::int32_t lat, lon;  // degE7
};

// Uploads `items` (MISSION_COUNT, then each as it is asked); returns the MISSION_ACK's type.
int upload(Rig& rig, Station& gcs, const std::vector<Item>& items, TimeUs& t) {
  mavlink_message_t m;
  mavlink_msg_mission_count_pack_status(255, 190, gcs.w.status(), &m, 1, 1,
                                        static_cast<std::uint16_t>(items.size()),
                                        MAV_MISSION_TYPE_MISSION, 0);
  rig.in(gcs.frame(m, t), t);
  for (std::size_t seq = 0; seq < items.size(); ++seq) {
    if (rig.out.back().msgid != MAVLINK_MSG_ID_MISSION_REQUEST_INT) return -1;
    const Item& it = items[seq];
    t += 1000;
    mavlink_msg_mission_item_int_pack_status(
        255, 190, gcs.w.status(), &m, 1, 1, static_cast<std::uint16_t>(seq),
        MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, it.cmd, 0, 1, it.p1, it.p2, 0, 0, it.lat, it.lon, 0,
        MAV_MISSION_TYPE_MISSION);
    rig.in(gcs.frame(m, t), t);
  }
  if (rig.out.back().msgid != MAVLINK_MSG_ID_MISSION_ACK) return -1;
  return mavlink_msg_mission_ack_get_type(&rig.out.back());
}

constexpr std::int32_t kLat = 473977000, kLon = 85455000;

TEST(MavlinkFly, ASpeedChangeAJumpAndALoiterFlyThroughTheSequencer) {
  Rig rig;
  Station gcs(test_key());
  TimeUs t = kT0;
  datum_t d{};
  d.utime = t;
  d.latitude = 47.3977;
  d.longitude = 8.5455;
  lcm_in(rig, channels::kDatum, d, t);
  // 0 A (11.13 N, 0); 1 speed 1.5 m/s; 2 B (0, 7.53 E); 3 jump to 0, once more;
  // 4 loiter 10 s at C (11.13 N, 7.53 E); 5 the datum (0, 0), the last item.
  const std::vector<Item> items = {
      {MAV_CMD_NAV_WAYPOINT, 0, 0, kLat + 1000, kLon},
      {MAV_CMD_DO_CHANGE_SPEED, 1, 1.5f, 0, 0},
      {MAV_CMD_NAV_WAYPOINT, 0, 0, kLat, kLon + 1000},
      {MAV_CMD_DO_JUMP, 0, 1, 0, 0},
      {MAV_CMD_NAV_LOITER_TIME, 10, 0, kLat + 1000, kLon + 1000},
      {MAV_CMD_NAV_WAYPOINT, 0, 0, kLat, kLon},
  };
  ASSERT_EQ(upload(rig, gcs, items, t), MAV_MISSION_ACCEPTED) << rig.texts();
  // Downloaded the same: the jump's target and repeat count, the loiter's time, the speed.
  mavlink_message_t m;
  for (std::uint16_t seq : {1, 3, 4}) {
    mavlink_msg_mission_request_int_pack_status(255, 190, gcs.w.status(), &m, 1, 1, seq,
                                                MAV_MISSION_TYPE_MISSION);
    t += 1000;
    rig.in(gcs.frame(m, t), t);
    ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_MISSION_ITEM_INT);
    EXPECT_EQ(mavlink_msg_mission_item_int_get_command(&rig.out.back()), items[seq].cmd);
    EXPECT_EQ(mavlink_msg_mission_item_int_get_param1(&rig.out.back()), items[seq].p1);
    EXPECT_EQ(mavlink_msg_mission_item_int_get_param2(&rig.out.back()), items[seq].p2);
  }
  odometry_t o{};
  o.utime = t;
  o.valid = odometry_t::VALID_POSITION;
  lcm_in(rig, channels::kOdometry, o, t);
  t += 1000;
  rig.in(gcs.command(MAV_CMD_MISSION_START, 0, 0, t), t);
  ASSERT_EQ(rig.out.back().msgid, MAVLINK_MSG_ID_COMMAND_ACK) << rig.texts();
  EXPECT_EQ(mavlink_msg_command_ack_get_result(&rig.out.back()), MAV_RESULT_ACCEPTED)
      << rig.texts();
  // Leg 1, to the loiter: the vehicle (0, 0), A, B, then the jump's repeat A, B, then C.
  auto paths = rig.bus.on<path_t>(channels::kPath);
  auto speeds = rig.bus.on<path_speed_t>(channels::kPathSpeed);
  ASSERT_EQ(paths.size(), 1u);
  ASSERT_EQ(speeds.size(), 1u);
  const double want[6][2] = {{0, 0}, {11.13, 0}, {0, 7.53}, {11.13, 0}, {0, 7.53}, {11.13, 7.53}};
  ASSERT_EQ(paths[0].n_waypoints, 6);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(paths[0].waypoints[i].position[0], want[i][0], 0.1) << i;
    EXPECT_NEAR(paths[0].waypoints[i].position[1], want[i][1], 0.1) << i;
  }
  // The speed: the follower's own (0) to A, 1.5 m/s from the speed item on, through the jump.
  EXPECT_EQ(speeds[0].path_id, paths[0].path_id);
  ASSERT_EQ(speeds[0].n_segments, 6);
  EXPECT_EQ(speeds[0].speed[0], 0.0);
  for (int i = 1; i < 6; ++i) EXPECT_EQ(speeds[0].speed[i], 1.5) << i;
  const auto starts = rig.bus.on<mission_command_t>(channels::kMissionCommand);
  ASSERT_EQ(starts.size(), 1u);
  EXPECT_EQ(starts[0].command, mission_command_t::START);
  // The follower completes leg 1 at C: the loiter's 10 s count from then.
  path_progress_t pr{};
  pr.utime = t;
  pr.path_id = paths[0].path_id;
  pr.complete = true;
  t += 20000;
  lcm_in(rig, channels::kPathProgress, pr, t);
  const TimeUs reached = t;
  rig.node->tick(reached + 9900000);
  EXPECT_EQ(rig.bus.on<path_t>(channels::kPath).size(), 1u);  // still loitering at 9.9 s
  rig.node->tick(reached + 10000000);
  paths = rig.bus.on<path_t>(channels::kPath);
  ASSERT_EQ(paths.size(), 2u);  // at 10 s: leg 2, C to the last item
  ASSERT_EQ(paths[1].n_waypoints, 2);
  EXPECT_NEAR(paths[1].waypoints[0].position[0], 11.13, 0.1);
  EXPECT_NEAR(paths[1].waypoints[1].position[0], 0, 0.1);
  EXPECT_NEAR(paths[1].waypoints[1].position[1], 0, 0.1);
  EXPECT_EQ(paths[1].path_id, paths[0].path_id + 1);
  EXPECT_EQ(rig.bus.on<path_speed_t>(channels::kPathSpeed).back().speed[1], 1.5);
}

TEST(MavlinkFly, AnUnknownCommandIsRefusedUnsupportedWithAStatusText) {
  Rig rig;
  Station gcs(test_key());
  TimeUs t = kT0;
  // 183 DO_SET_SERVO: the .plan support refuses servo commands (no outputs on our vehicles).
  ASSERT_EQ(upload(rig, gcs, {{MAV_CMD_NAV_WAYPOINT, 0, 0, kLat, kLon}, {183, 1, 1500, 0, 0}}, t),
            MAV_MISSION_UNSUPPORTED);
  EXPECT_TRUE(rig.node->mission(MAV_MISSION_TYPE_MISSION).empty());
  EXPECT_NE(rig.texts().find("item 1 (command 183)"), std::string::npos) << rig.texts();
}

}  // namespace
}  // namespace tiller::mavlink
