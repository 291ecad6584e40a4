// tiller-mavlink's controller gains as parameters (mavlink/mavlink_gains.hpp): read from the
// shipped control configs by lib/control's loaders, listed after the bridge's own, bounds the
// loaders' (refused with a STATUSTEXT), an accepted set kept by the bridge and said to be.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "mavlink/mavlink_gains.hpp"
#include "mavlink_rig.hpp"

namespace tiller::mavlink {
namespace {

const GainParam* find(const std::vector<GainParam>& g, const std::string& id) {
  for (const auto& p : g)
    if (p.id == id) return &p;
  return nullptr;
}

TEST(MavlinkGains, TheOttersGainsComeFromItsControlConfig) {
  const auto g = load_gain_params(TILLER_SOURCE_DIR "/config/control/otter.yaml");
  EXPECT_EQ(g.size(), 3u * 6 + 2 + 3 * 5);  // velocity_pid 3 axes x 6, heading, yaw rate; SK 3 x 5
  for (const auto& p : g) EXPECT_LE(p.id.size(), 16u) << p.id;
  ASSERT_NE(find(g, "VP_SURGE_KERR"), nullptr);
  EXPECT_EQ(find(g, "VP_SURGE_KERR")->value, 150);  // otter.yaml velocity_pid.surge.k_error
  EXPECT_EQ(find(g, "VP_SURGE_KERR")->key, "velocity_pid.surge.k_error");
  EXPECT_EQ(find(g, "SK_YAW_KP")->value, 60);
  EXPECT_EQ(find(g, "VP_HEADING_KP")->value, 1.0);
  EXPECT_EQ(find(g, "SK_X_KI")->min, 0);      // Range::at_least(0)
  EXPECT_GT(find(g, "SK_X_MAXOUT")->min, 0);  // Range::positive()
}

TEST(MavlinkGains, TheRovsPerAxisGainsComeFromItsControlConfig) {
  const auto g = load_gain_params(TILLER_SOURCE_DIR "/config/control/bluerov2.yaml");
  EXPECT_EQ(g.size(), 6u * 7);
  for (const auto& p : g) EXPECT_LE(p.id.size(), 16u) << p.id;
  EXPECT_EQ(find(g, "ROV_HEAVE_KP")->value, 1512);
  EXPECT_EQ(find(g, "ROV_SURGE_PILOT")->value, 0.7);
  EXPECT_EQ(find(g, "ROV_SURGE_PILOT")->max, 1.0);  // {0, 1}
  EXPECT_EQ(find(g, "ROV_YAW_KIRATE")->key, "rov_control.axes.yaw.ki_rate");
}

std::vector<mavlink_message_t> values(const Rig& rig) {
  std::vector<mavlink_message_t> v;
  for (const auto& m : rig.out)
    if (m.msgid == MAVLINK_MSG_ID_PARAM_VALUE) v.push_back(m);
  return v;
}

TEST(MavlinkGains, AGainIsListedSetInBoundsAndRefusedOutside) {
  Rig rig(true, load_gain_params(TILLER_SOURCE_DIR "/config/control/otter.yaml"));
  const std::size_t total = kParamCount + rig.node->gains().size();
  Station gcs(test_key());
  mavlink_message_t m;
  mavlink_msg_param_request_list_pack_status(255, 190, gcs.w.status(), &m, 1, 1);
  rig.in(gcs.frame(m, kT0), kT0);
  auto v = values(rig);
  ASSERT_EQ(v.size(), total);
  EXPECT_EQ(mavlink_msg_param_value_get_param_count(&v.back()), total);
  char id[17] = {};
  mavlink_msg_param_value_get_param_id(&v[kParamCount], id);
  EXPECT_STREQ(id, "VP_SURGE_KDRAG");
  // Read by name.
  char want[16] = {};
  std::strncpy(want, "SK_YAW_KP", sizeof want);
  mavlink_msg_param_request_read_pack_status(255, 190, gcs.w.status(), &m, 1, 1, want, -1);
  rig.in(gcs.frame(m, kT0 + 500), kT0 + 500);
  EXPECT_EQ(mavlink_msg_param_value_get_param_value(&rig.out.back()), 60.0f);
  // Below the loader's 0: refused, the old value sent back.
  std::strncpy(want, "VP_SURGE_KERR", sizeof want);
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, want, -1.0f,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 1000), kT0 + 1000);
  EXPECT_EQ(mavlink_msg_param_value_get_param_value(&rig.out.back()), 150.0f);
  EXPECT_NE(rig.texts().find("VP_SURGE_KERR refused: -1, not >= 0"), std::string::npos)
      << rig.texts();
  // max_output must be > 0: 0 refused.
  std::strncpy(want, "SK_X_MAXOUT", sizeof want);
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, want, 0.0f,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 1500), kT0 + 1500);
  EXPECT_NE(rig.texts().find("SK_X_MAXOUT refused: 0, not > 0"), std::string::npos);
  EXPECT_EQ(find(rig.node->gains(), "SK_X_MAXOUT")->value, 200);
  // In bounds: kept by the bridge, and it says the controller does not have it.
  std::strncpy(want, "VP_SURGE_KERR", sizeof want);
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, want, 160.0f,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 2000), kT0 + 2000);
  EXPECT_EQ(mavlink_msg_param_value_get_param_value(&rig.out.back()), 160.0f);
  EXPECT_EQ(find(rig.node->gains(), "VP_SURGE_KERR")->value, 160);
  EXPECT_NE(rig.texts().find("VP_SURGE_KERR=160 set in bridge only (not live)"), std::string::npos)
      << rig.texts();
  EXPECT_EQ(gains_diff(rig.node->gains()), "velocity_pid.surge.k_error: 160 (was 150)\n");
  // NaN: refused.
  mavlink_msg_param_set_pack_status(255, 190, gcs.w.status(), &m, 1, 1, want, NAN,
                                    MAV_PARAM_TYPE_REAL32);
  rig.in(gcs.frame(m, kT0 + 3000), kT0 + 3000);
  EXPECT_EQ(find(rig.node->gains(), "VP_SURGE_KERR")->value, 160);
}

TEST(MavlinkGains, TheConfigKeyLoadsTheControlFile) {
  const auto root = config::Value::parse("control_config: config/control/otter.yaml\n",
                                         TILLER_SOURCE_DIR "/config/mavlink/x.yaml");
  const MavlinkConfig c = load_mavlink(root, "");
  EXPECT_EQ(c.node.gains.size(), 35u);
  const auto bad = config::Value::parse("control_config: config/control/nothere.yaml\n",
                                        TILLER_SOURCE_DIR "/config/mavlink/x.yaml");
  EXPECT_THROW(load_mavlink(bad, ""), std::exception);
}

}  // namespace
}  // namespace tiller::mavlink
