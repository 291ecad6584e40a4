// The mixer's steady state allocates nothing: after a warm-up, MixerNode in lockstep with a
// feeder publishing the manual demand, both wrenches, the arm state and the arbitration (the
// source switching between them, saturating and not) runs 10 s with zero heap allocations.
// operator new is counted for this whole binary.
#include <gtest/gtest.h>

#include <cmath>

#include <tiller/power_t.hpp>

#include "alloc_count.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller {
namespace {

class Feeder : public Node {
 public:
  Feeder() : Node("feeder", 10'000) {
    arm_.armed = true;
    arm_.reason = "test feeder";
    arb_.reason = "test feeder";
    power_.monitor = "test";
  }
  void on_tick(TimeUs now) override {
    const double s = std::sin(1e-6 * static_cast<double>(now));
    ++k_;
    manual_.utime = now;
    manual_.valid = true;
    manual_.demand[0] = s;
    manual_.demand[1] = 0.5 * s;
    manual_.demand[5] = -s;
    publish(channels::kManualDemand, manual_);
    wrench_.utime = now;
    wrench_.valid = true;
    wrench_.tau[0] = 300 * s;  // saturates at the peaks
    wrench_.tau[5] = 10 * s;
    wrench_.tau[2] = -20;
    publish(channels::kWrenchVelocity, wrench_);
    publish(channels::kWrenchStation, wrench_);
    arm_.utime = now;
    // From the first tick, when the stick is centred (sin 0): the safety gate opens at once.
    if (k_ % 10 == 0 || k_ == 1) publish(channels::kArmState, arm_);
    if (k_ % 10 == 0) {  // the battery sagging and recovering, 12..16 V
      power_.utime = now;
      power_.voltage = 14 + 2 * s;
      power_.current = 10;
      power_.power = 10 * power_.voltage;
      publish(channels::kPower, power_);
    }
    if (k_ % 50 == 0) {
      arb_.utime = now;
      arb_.active_source = static_cast<std::int8_t>(1 + (k_ / 50) % 3);
      publish(channels::kArbitration, arb_);
    }
  }

 private:
  long k_ = 0;
  manual_demand_t manual_{};
  wrench_t wrench_{};
  arm_state_t arm_{};
  arbitration_t arb_{};
  power_t power_{};
};

TEST(MixerAllocation, SteadyStateAllocatesNothing) {
  MixerNode mixer(std::string(TILLER_SOURCE_DIR) + "/config/mixer/seed001_rov6.yaml");
  Feeder feeder;
  LockstepExecutor ex(0);
  ex.add(feeder);
  ex.add(mixer);
  ex.run_until(3 * kUsPerSecond);  // warm-up: buffers and heartbeat strings reach their size
  const long before = test::allocations();
  ex.run_until(13 * kUsPerSecond);
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << "heap allocations in 10 s of steady-state mixing";
  EXPECT_GT(mixer.received(), 4000);
  // 13 s of 50 Hz ticks plus the active source's 100 Hz input, command + status each: ~3900.
  EXPECT_GT(mixer.published(), 3500);
  EXPECT_TRUE(mixer.last_command().armed);
}

// The same with thrusters whose curve follows the battery (curve: t200): each TILLER_POWER
// re-blends the tables, still without an allocation.
TEST(MixerAllocation, TheSupplyVoltageAllocatesNothing) {
  MixerNode mixer(std::string(TILLER_SOURCE_DIR) + "/test/mixer/data/t200_pair_mixer.yaml");
  ASSERT_TRUE(mixer.allocator().voltage_dependent());
  Feeder feeder;
  LockstepExecutor ex(0);
  ex.add(feeder);
  ex.add(mixer);
  ex.run_until(3 * kUsPerSecond);
  const long before = test::allocations();
  ex.run_until(13 * kUsPerSecond);
  EXPECT_EQ(test::allocations() - before, 0) << "heap allocations in 10 s with the voltage";
  EXPECT_EQ(mixer.counter_value("rejected.power.invalid"), 0);
  EXPECT_EQ(mixer.counter_value("supply_voltage.stale"), 0);
}

}  // namespace
}  // namespace tiller
