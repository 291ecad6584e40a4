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

// Node::on_time through a real node: an odometry message older by its utime than the teleop's
// odometry limit (odometry_timeout) + the clock offset bound is counted in
// rejected.odometry.stale, one ahead by more than the bound in rejected.odometry.future, and
// neither is taken; the bound is the one the executor set (Node::set_clock_offset).
TEST(NodeChecks, OdometryIsRefusedByItsOwnTimeStamp) {
  const TeleopParams p =
      load_teleop_file(TILLER_SOURCE_DIR "/config/teleop/extreme3dpro_seed000.yaml");
  TeleopNode node(p, TeleopNode::Input::replay);
  node.set_clock_offset(100'000);
  EXPECT_EQ(node.clock_offset(), 100'000);
  const TimeUs limit = p.odometry_timeout;
  const TimeUs now = 50'000'000;
  auto send = [&](TimeUs utime) {
    odometry_t o{};
    o.utime = utime;
    const Event e = encode("TILLER_ODOMETRY", 0, o);
    node.deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), now);
  };
  send(now - limit - 100'000);  // exactly limit + bound old: taken
  send(now - limit - 100'001);  // 1 us more: stale
  send(now + 100'000);          // exactly the bound ahead: taken
  send(now + 100'001);          // 1 us more: from the future
  send(0);                      // a sender that never stamps
  EXPECT_EQ(node.counter_value("rejected.odometry.stale"), 2);
  EXPECT_EQ(node.counter_value("rejected.odometry.future"), 1);
  EXPECT_EQ(node.rejected(), 3);
  EXPECT_EQ(node.received(), 5);
}

}  // namespace
}  // namespace tiller
