// Message checks applied inside a node: tiller-teleop's odometry input goes through
// core/message_checks.hpp, so a heading outside (-pi, pi] or a bad covariance is dropped and
// counted (rejected.odometry.range), a NaN anywhere (not only in the yaw) under .nan, and a
// good message is accepted.
#include <gtest/gtest.h>

#include <cmath>

#include "runtime/event.hpp"
#include "teleop/teleop_node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller {
namespace {

TEST(NodeChecks, TeleopOdometryUsesTheContractCheck) {
  TeleopNode node(load_teleop_file(TILLER_SOURCE_DIR "/config/teleop/extreme3dpro_seed000.yaml"),
                  TeleopNode::Input::replay);
  auto send = [&](const odometry_t& o) {
    const Event e = encode("TILLER_ODOMETRY", 0, o);
    node.deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), 1000);
  };
  odometry_t good{};
  good.orientation[2] = 3.0;
  send(good);
  EXPECT_EQ(node.rejected(), 0);

  odometry_t o = good;
  o.orientation[2] = 4.0;  // outside (-pi, pi]
  send(o);
  o = good;
  o.n_pose_cov = 9;  // must be 0 or 36
  o.pose_covariance.assign(9, 0.0);
  send(o);
  EXPECT_EQ(node.counter_value("rejected.odometry.range"), 2);

  o = good;
  o.velocity[3] = std::nan("");  // the old check looked at the yaw only
  send(o);
  o = good;
  o.position[0] = INFINITY;
  send(o);
  EXPECT_EQ(node.counter_value("rejected.odometry.nan"), 2);
  EXPECT_EQ(node.rejected(), 4);
  EXPECT_EQ(node.received(), 5);
}

}  // namespace
}  // namespace tiller
