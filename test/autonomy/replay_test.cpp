// Log replay of the autonomy: a closed-loop mission on the full stack is recorded in lockstep;
// replaying the recorded inputs through fresh path-follower, velocity-PID and station-keep
// nodes gives their recorded outputs back bit for bit (what tiller-replay relies on).
#include <gtest/gtest.h>

#include <set>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission_node.hpp"
#include "plants.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/replay.hpp"

namespace tiller::test {
namespace {

struct Nodes {
  guidance::PathFollowerNode follower{guidance::load_follower_node_params(
      config::Value::load_file(source_path("config/guidance/default.yaml")))};
  control::VelocityPidNode vpid{control::load_velocity_pid_node_params(
      config::Value::load_file(source_path("config/control/seed004_usv_x.yaml")))};
  control::StationKeepNode skeep{control::load_station_keep_node_params(
      config::Value::load_file(source_path("config/control/seed004_usv_x.yaml")))};
};

std::vector<Event> only(const std::vector<Event>& all, const std::set<std::string>& channels) {
  std::vector<Event> out;
  for (const auto& e : all) {
    if (channels.count(e.channel)) out.push_back(e);
  }
  return out;
}

void expect_replay_identical(Node& fresh, const std::vector<Event>& log,
                             const std::set<std::string>& outputs, TimeUs end) {
  ReplayExecutor rx(fresh);
  rx.run(log, TimeUs{0}, end);
  const auto want = only(log, outputs);
  const auto got = only(rx.outputs(), outputs);
  ASSERT_EQ(got.size(), want.size()) << fresh.name();
  for (std::size_t k = 0; k < got.size(); ++k) {
    ASSERT_EQ(got[k].channel, want[k].channel) << fresh.name() << " event " << k;
    ASSERT_EQ(got[k].time, want[k].time) << fresh.name() << " event " << k;
    ASSERT_EQ(got[k].data, want[k].data)
        << fresh.name() << " event " << k << " on " << got[k].channel;
  }
}

TEST(Replay, AutonomyNodesReplayBitForBit) {
  const auto m = mission::load_mission_file(source_path("config/missions/default.yaml"));
  const auto& plant = plants()[1];  // seed004_usv_x, full stack
  auto plant_nodes = plant.make(m, 0.3, 0.5);
  Nodes live;
  mission::MissionNode mnode(m, 1, kUsPerSecond);
  LockstepExecutor ex(0);
  for (auto& n : plant_nodes) ex.add(*n);
  ex.add(mnode);
  ex.add(live.follower);
  ex.add(live.vpid);
  ex.add(live.skeep);
  std::vector<Event> log;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    log.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
  });
  const TimeUs end = 75 * kUsPerSecond;  // through the hand-over to station keeping
  ex.run_until(end);
  ASSERT_TRUE(live.skeep.active());

  Nodes fresh;
  expect_replay_identical(fresh.follower, log,
                          {"TILLER_VELOCITY_SETPOINT", "TILLER_PATH_PROGRESS",
                           "TILLER_STATION_TARGET", "TILLER_HEARTBEAT_PATH_FOLLOWER"},
                          end);
  expect_replay_identical(fresh.vpid, log,
                          {"TILLER_ARBITRATION", "TILLER_WRENCH_VELOCITY", "TILLER_PID_VELOCITY",
                           "TILLER_HEARTBEAT_VELOCITY_PID"},
                          end);
  expect_replay_identical(
      fresh.skeep, log,
      {"TILLER_WRENCH_STATION", "TILLER_PID_STATION", "TILLER_HEARTBEAT_STATION_KEEP"}, end);
}

}  // namespace
}  // namespace tiller::test
