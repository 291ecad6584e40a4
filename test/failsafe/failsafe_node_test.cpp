// tiller-failsafe's node and odometry_t.valid: a depth flagged invalid (VALID_DEPTH clear, a
// pressure sensor lost) is no depth reading. Below the depth limit by its (invalid) number, the
// node starts no rise; each such message is counted in odometry.depth_invalid and the heartbeat
// is DEGRADED naming why, not OK with "no failsafe event" (the old node took the number and rose
// on it).
#include <gtest/gtest.h>

#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include <string>

#include "failsafe/failsafe_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::failsafe {
namespace {

// The node in lockstep, its latest vehicle status and heartbeat kept.
struct Rig {
  explicit Rig(const FailsafeNodeParams& p) : node(p), ex(0) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kVehicleStatus) status.decode(d, 0, n);
      if (ch == node.heartbeat_channel()) hb.decode(d, 0, n);
    });
  }
  FailsafeNode node;
  LockstepExecutor ex;
  vehicle_status_t status{};
  heartbeat_t hb{};
};

TEST(FailsafeNode, AnInvalidDepthIsNoReadingForTheDepthLimit) {
  FailsafeNodeParams p;
  p.monitor.depth.enabled = true;
  p.monitor.depth.limit_m = 10;
  Rig rig(p);
  FailsafeNode& node = rig.node;
  LockstepExecutor& ex = rig.ex;
  const vehicle_status_t& status = rig.status;
  const heartbeat_t& hb = rig.hb;
  // 0-2 s: a valid 9 m; 2-4 s: the depth flagged invalid, its number 50 m (whatever the
  // estimator last had).
  int invalid = 0;
  for (TimeUs t = 0; t < 4'000'000; t += 100'000) {
    odometry_t o{};
    o.utime = t;
    const bool lost = t >= 2'000'000;
    o.valid = lost ? int{odometry_t::VALID_ATTITUDE} : int{odometry_t::VALID_ALL};
    o.position[2] = lost ? 50.0 : 9.0;
    invalid += lost ? 1 : 0;
    ex.inject(channels::kOdometry, o, t);
  }
  ex.run_until(1'950'000);
  EXPECT_EQ(status.action, vehicle_status_t::ACTION_NONE);
  EXPECT_EQ(hb.state, heartbeat_t::STATE_OK) << hb.status;
  ex.run_until(3'950'000);
  EXPECT_EQ(status.action, vehicle_status_t::ACTION_NONE) << status.reason;
  EXPECT_EQ(status.latched & vehicle_status_t::EVENT_DEPTH_LIMIT, 0);
  EXPECT_EQ(node.counter_value("odometry.depth_invalid"), invalid);
  EXPECT_EQ(node.rejected(), 0);  // well-formed messages: not bad input
  EXPECT_EQ(hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_EQ(std::string(hb.status),
            "odometry depth invalid: the depth rule is blind (keeps its last verdict)");
}

// The same for the geofence: an invalid position (VALID_POSITION clear) outside the fence starts
// no hold; each such message is counted in odometry.position_invalid and the heartbeat says the
// geofence is blind.
TEST(FailsafeNode, AnInvalidPositionIsNoReadingForTheGeofence) {
  FailsafeNodeParams p;
  p.monitor.geofence.enabled = true;
  p.monitor.geofence.polygon = {{0, 0}, {0, 100}, {100, 100}, {100, 0}};
  Rig rig(p);
  FailsafeNode& node = rig.node;
  LockstepExecutor& ex = rig.ex;
  const vehicle_status_t& status = rig.status;
  const heartbeat_t& hb = rig.hb;
  // 0-2 s: valid, 50 m inside; 2-4 s: the position flagged invalid, its number 150 m north
  // (outside) and moving out at 1 m/s.
  int invalid = 0;
  for (TimeUs t = 0; t < 4'000'000; t += 100'000) {
    odometry_t o{};
    o.utime = t;
    const bool lost = t >= 2'000'000;
    o.valid = lost ? int{odometry_t::VALID_ALL & ~odometry_t::VALID_POSITION}
                   : int{odometry_t::VALID_ALL};
    o.position[0] = lost ? 150.0 : 50.0;
    o.position[1] = 50.0;
    o.velocity[0] = lost ? 1.0 : 0.0;
    invalid += lost ? 1 : 0;
    ex.inject(channels::kOdometry, o, t);
  }
  ex.run_until(1'950'000);
  EXPECT_EQ(status.action, vehicle_status_t::ACTION_NONE);
  EXPECT_EQ(hb.state, heartbeat_t::STATE_OK) << hb.status;
  ex.run_until(3'950'000);
  EXPECT_EQ(status.action, vehicle_status_t::ACTION_NONE) << status.reason;
  EXPECT_EQ(status.latched & vehicle_status_t::EVENT_GEOFENCE, 0);
  EXPECT_EQ(node.counter_value("odometry.position_invalid"), invalid);
  EXPECT_EQ(node.rejected(), 0);
  EXPECT_EQ(hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_EQ(std::string(hb.status),
            "odometry position invalid: the geofence is blind (keeps its last verdict)");
}

}  // namespace
}  // namespace tiller::failsafe
