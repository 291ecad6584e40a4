// Steady-state message flow allocates nothing: after a warm-up, a lockstep closed loop
// (encode, queue, decode into the reused target, handler, tick) runs with zero heap
// allocations. operator new is counted for this whole binary.
#include <gtest/gtest.h>

#include "alloc_count.hpp"
#include "echo_node.hpp"
#include "runtime/lockstep.hpp"

namespace tiller {
namespace {

TEST(Allocation, LockstepSteadyStateAllocatesNothing) {
  test::ToyController c;
  test::ToyPlant p;
  LockstepExecutor ex(0);
  ex.add(p);
  ex.add(c);
  ex.run_until(3 * kUsPerSecond);  // warm-up: buffers and heartbeat strings reach their size
  const long before = test::allocations();
  ex.run_until(13 * kUsPerSecond);  // 1000 plant ticks, 500 controller ticks, 1500 deliveries
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << "heap allocations in 10 s of steady-state lockstep";
  EXPECT_GT(c.received(), 1000);
}

// The live executor counts missed ticks when a loaded machine makes it fall behind, which can
// first happen long after a warm-up: that first miss must not allocate (the counter was made
// lazily on it, which made runtime_live_alloc_test fail under load: 1-5 allocations).
TEST(Allocation, FirstMissedTickAfterWarmUpAllocatesNothing) {
  test::ToyController c;
  for (int i = 0; i < 100; ++i) c.count_missed_ticks(0);  // warm-up: on time
  const long before = test::allocations();
  c.count_missed_ticks(3);
  c.count_missed_ticks(0);
  c.count_missed_ticks(2);
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << "heap allocations counting the first missed ticks";
  EXPECT_EQ(c.counter_value("ticks.missed"), 5);
  EXPECT_EQ(c.counter_value("ticks.run"), 103);
}

}  // namespace
}  // namespace tiller
