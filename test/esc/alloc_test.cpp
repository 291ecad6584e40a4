// An ESC cycle allocates nothing: command delivery, the safety logic, the bus transactions,
// telemetry reads, and the 10 Hz / 1 Hz messages, for each backend, after a warm-up.
#include <gtest/gtest.h>

#include "alloc_count.hpp"
#include "esc_setups.hpp"

namespace tiller::test {
namespace {

void expect_no_allocation(const std::string& backend, int n) {
  Steady s(backend, n);
  for (int k = 0; k < 300; ++k) s.cycle();  // warm-up: first heartbeat, first status
  const long before = allocations();
  for (int k = 0; k < 3000; ++k) s.cycle();  // 30 s: 300 status messages, 30 heartbeats
  EXPECT_EQ(allocations() - before, 0) << backend << " with " << n << " ESCs";
  EXPECT_TRUE(s.node->armed());
  EXPECT_NE(s.node->last_output().value[1], s.node->backend().to_hardware(1, 0.0));
}

TEST(EscAllocation, TgyCycleAllocatesNothing) {
  expect_no_allocation("i2c_tgy", 4);
  expect_no_allocation("i2c_tgy", 8);
}
TEST(EscAllocation, Pca9685CycleAllocatesNothing) {
  expect_no_allocation("pca9685", 8);
}
TEST(EscAllocation, SimCycleAllocatesNothing) {
  expect_no_allocation("sim", 4);
}

TEST(EscAllocation, CounterWorks) {
  const long before = allocations();
  auto* p = new int(3);
  EXPECT_EQ(allocations() - before, 1);
  delete p;
}

}  // namespace
}  // namespace tiller::test
