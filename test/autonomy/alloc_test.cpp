// The autonomy's steady state allocates nothing: after a warm-up, the path follower, the
// velocity PID (with the arbiter), the station keeper and the mission publisher, closed around
// the stand-in plant in lockstep, run 20 s of following and 20 s of station keeping with zero
// heap allocations. operator new is counted for this whole binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission_node.hpp"
#include "runtime/lockstep.hpp"
#include "simple_plant.hpp"

namespace {
std::atomic<long> g_allocs{0};
}
void* operator new(std::size_t n) {
  ++g_allocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

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
  ex.run_until(3 * kUsPerSecond);  // warm-up: buffers and status strings reach their size
  long before = g_allocs.load();
  ex.run_until(10 * kUsPerSecond);  // following the path
  EXPECT_EQ(g_allocs.load() - before, 0) << "heap allocations while following";
  EXPECT_FALSE(follower.last_output().complete);
  ex.run_until(25 * kUsPerSecond);  // arrives, hands over (warm-up of the station strings)
  before = g_allocs.load();
  ex.run_until(45 * kUsPerSecond);
  EXPECT_EQ(g_allocs.load() - before, 0) << "heap allocations while station keeping";
  EXPECT_TRUE(skeep.active());
}

}  // namespace
}  // namespace tiller::test
