// The autonomy allocates nothing in steady state, hand-overs included: the path follower, the
// velocity PID (with the arbiter), the station keeper and the mission publisher, closed around
// the stand-in plant in lockstep, follow the path (no allocation), hand over to station
// keeping on arrival, then hand over back and forth ten times on mode changes; after the first
// hand-over of each kind, 18 more switches allocate nothing. The arbitration reason and the
// status lines are sized at construction. operator new is counted for this whole binary.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/wrench_t.hpp>

#include <cstdio>

#include "alloc_count.hpp"
#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "simple_plant.hpp"

namespace tiller::test {
namespace {

TEST(Allocation, AutonomySteadyStateAllocatesNothing) {
  const auto m = mission::load_mission_file(source_path("config/missions/station_keeping.yaml"));
  SimplePlant plant(0.3, 0.5);
  guidance::PathFollowerNode follower(guidance::load_follower_node_params(
      config::Value::load_file(source_path("config/guidance/default.yaml"))));
  const auto ctl = source_path("config/control/otter.yaml");
  control::VelocityPidNode vpid(
      control::load_velocity_pid_node_params(config::Value::load_file(ctl)));
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(ctl)));
  mission::MissionNode mnode(m, 1, kUsPerSecond);
  LockstepExecutor ex(0);
  ex.add(plant);
  ex.add(mnode);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);
  int switches = 0, vpid_to_sk = 0, sk_to_vpid = 0;
  std::int8_t source = -1;
  arbitration_t arb{};
  arb.reason.reserve(256);
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch != channels::kArbitration || arb.decode(d, 0, n) != n) return;
    if (source >= 0 && arb.active_source != source) {
      ++switches;
      if (source == wrench_t::SOURCE_VELOCITY_PID &&
          arb.active_source == wrench_t::SOURCE_STATION_KEEP)
        ++vpid_to_sk;
      if (source == wrench_t::SOURCE_STATION_KEEP &&
          arb.active_source == wrench_t::SOURCE_VELOCITY_PID)
        ++sk_to_vpid;
    }
    source = arb.active_source;
  });
  // From 30 s, at every half second a manual closed-loop request (velocity PID), undone by the
  // mission's waypointing at the next whole second (station keeping again): hand-overs both
  // ways, with mode changes, every second. Injected events are queued before the measurement.
  controller_mode_t manual{};
  manual.mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  manual.source = "alloc-test";
  for (TimeUs t = 30'500'000; t < 40 * kUsPerSecond; t += kUsPerSecond) {
    manual.utime = t;
    ex.inject(channels::kMode, manual, t);
  }
  ex.run_until(3 * kUsPerSecond);  // warm-up: buffers reach their size
  long before = allocations();
  ex.run_until(10 * kUsPerSecond);  // following the path
  EXPECT_EQ(allocations() - before, 0) << "heap allocations while following";
  EXPECT_FALSE(follower.last_output().complete);
  EXPECT_EQ(vpid.decision().source, wrench_t::SOURCE_VELOCITY_PID);
  // The first hand-over of each kind (arrival at 13 s, the first mode change at 30.5 s) is
  // part of the warm-up: the runtime's reused buffers (lockstep queue slots, encode buffers,
  // subscription decode targets) grow once to the longest arbitration and heartbeat messages.
  // The nodes' own strings are sized at construction and do not count here.
  before = allocations();
  ex.run_until(31'250'000);  // station keeping again after the first round trip
  const long first_of_kind = allocations() - before;
  EXPECT_TRUE(skeep.active());
  const int measured_from = switches;
  before = allocations();
  ex.run_until(45 * kUsPerSecond);  // nine more station-keep <-> velocity-PID round trips
  EXPECT_EQ(allocations() - before, 0) << "heap allocations across the hand-overs";
  EXPECT_TRUE(skeep.active());
  EXPECT_GE(vpid_to_sk, 10);
  EXPECT_GE(sk_to_vpid, 10);
  EXPECT_GE(switches - measured_from, 18);
  std::printf(
      "%d arbitration changes measured with no allocation (of %d: %d velocity PID -> station "
      "keeping, %d back); %ld one-off buffer growths at the first of each kind\n",
      switches - measured_from, switches, vpid_to_sk, sk_to_vpid, first_of_kind);
}

}  // namespace
}  // namespace tiller::test
