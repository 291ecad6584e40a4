// MixerNode and tiller-failsafe: a thruster test is refused while any failsafe is active
// (TILLER_VEHICLE_STATUS with an event holding or an action beyond WARN) or the failsafe is in
// control (its wrench), even while the gate waits neutral, and the refusal names the failsafe; a
// failsafe becoming active ends a running test at once (docs/safety.md, "Thruster test").
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/thruster_test_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/wrench_t.hpp>

#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller {
namespace {

struct Rig {
  Rig() : node(std::string(TILLER_SOURCE_DIR) + "/config/mixer/seed000_rov4.yaml"), ex(0) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      if (ch != channels::kThrusterCommand) return;
      ASSERT_EQ(last.decode(d, 0, n), n);
      last_t = t;
    });
  }
  void arm(TimeUs at) {
    arm_state_t a{};
    a.utime = at;
    a.armed = true;
    a.session = 1;
    ex.inject(channels::kArmState, a, at);
  }
  void centred_stick(TimeUs at) {
    manual_demand_t m{};
    m.utime = at;
    m.valid = true;
    ex.inject(channels::kManualDemand, m, at);
  }
  void status(TimeUs at, std::int32_t active, std::int8_t action, const char* reason) {
    vehicle_status_t s{};
    s.utime = at;
    s.active = active;
    s.latched = active;
    s.action = action;
    s.reason = reason;
    ex.inject(channels::kVehicleStatus, s, at);
  }
  void failsafe_wrench(TimeUs at) {  // tiller-failsafe's NEUTRAL: a valid zero wrench
    wrench_t w{};
    w.utime = at;
    w.source = wrench_t::SOURCE_FAILSAFE;
    w.valid = true;
    ex.inject(channels::kWrenchFailsafe, w, at);
  }
  void press(TimeUs at, std::int64_t id) {
    thruster_test_t t{};
    t.utime = at;
    t.test_id = id;
    t.active = true;
    t.thruster = 2;
    t.command = 0.1;
    t.source = "cockpit";
    ex.inject(channels::kThrusterTest, t, at);
  }
  bool neutral() const {
    for (double v : last.command)
      if (v != 0.0) return false;
    return true;
  }
  MixerNode node;
  LockstepExecutor ex;
  thruster_command_t last{};
  TimeUs last_t = -1;
};

TEST(MixerFailsafe, AnActiveFailsafeRefusesAThrusterTestAndEndsARunningOne) {
  Rig r;
  r.arm(5'000);
  r.centred_stick(5'000);
  r.ex.run_until(10'000);
  ASSERT_EQ(r.last.gate, thruster_command_t::GATE_ACTIVE);  // the centred pilot in control
  r.status(10'000, vehicle_status_t::EVENT_GEOFENCE, vehicle_status_t::ACTION_HOLD, "geofence");
  r.press(11'000, 5);
  r.ex.run_until(11'000);
  EXPECT_EQ(r.last_t, 11'000);
  EXPECT_NE(r.last.gate, thruster_command_t::GATE_TEST);
  EXPECT_TRUE(r.neutral());
  EXPECT_EQ(r.last.hold,
            "thruster test refused: a failsafe is active (tiller-failsafe: HOLD: geofence; clear "
            "it first)");
  EXPECT_EQ(r.node.counter_value("thruster_test.refused"), 1);
  EXPECT_EQ(r.node.counter_value("thruster_test.started"), 0);
  // Cleared: a new press is taken.
  r.status(50'000, 0, vehicle_status_t::ACTION_NONE, "ok");
  r.press(60'000, 6);
  r.ex.run_until(60'000);
  ASSERT_EQ(r.last.gate, thruster_command_t::GATE_TEST);
  EXPECT_EQ(r.last.command, (std::vector<double>{0, 0, 0.1, 0}));
  // A leak during the test: ended at once, neutral, named.
  r.status(70'000, vehicle_status_t::EVENT_LEAK, vehicle_status_t::ACTION_NEUTRAL, "leak");
  r.ex.run_until(70'000);
  EXPECT_EQ(r.last_t, 70'000);
  EXPECT_NE(r.last.gate, thruster_command_t::GATE_TEST);
  EXPECT_TRUE(r.neutral());
  EXPECT_EQ(r.last.hold,
            "thruster test ended: a failsafe is active (tiller-failsafe: NEUTRAL: leak; press "
            "again)");
  // A bad status is dropped and counted; the last good one stays in force.
  r.status(80'000, 1 << 10, vehicle_status_t::ACTION_NONE, "bad bits");
  r.press(90'000, 7);
  r.ex.run_until(90'000);
  EXPECT_EQ(r.node.counter_value("rejected.vehicle_status.invalid"), 1);
  EXPECT_NE(r.last.gate, thruster_command_t::GATE_TEST);
}

// The reported case: tiller-failsafe's wrench in control while the gate waits (armed, nothing
// moved in this arming), no vehicle status heard: the press used to enter TEST.
TEST(MixerFailsafe, TheFailsafeInControlWaitingRefusesAThrusterTest) {
  Rig r;
  r.arm(5'000);
  r.failsafe_wrench(5'000);
  r.ex.run_until(10'000);
  ASSERT_EQ(r.last.gate, thruster_command_t::GATE_WAIT_NEUTRAL);
  r.press(11'000, 5);
  r.ex.run_until(11'000);
  EXPECT_EQ(r.last_t, 11'000);
  EXPECT_EQ(r.last.gate, thruster_command_t::GATE_WAIT_NEUTRAL);
  EXPECT_TRUE(r.neutral());
  EXPECT_EQ(r.last.hold,
            "thruster test refused: the failsafe is in control (tiller-failsafe: its wrench or "
            "hold in force; clear it first)");
  EXPECT_EQ(r.node.counter_value("thruster_test.started"), 0);
}

}  // namespace
}  // namespace tiller
