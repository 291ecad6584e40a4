// The mixer on a vehicle whose thrust depends on the battery voltage (curve: t200, the 12 and
// 16 V sheets of Blue Robotics' T200 data blended by ThrustCurve::voltage_table): each
// TILLER_POWER sets the voltage thrust becomes commands at, so the same demand gives the same
// thrust at 12 V as at 16 V (a larger command at 12 V); no power, or none for 2 s, is the 16 V
// table (the least thrust for a command); a bad sample is refused and counted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <tiller/arm_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "vehicle/thrust_curve.hpp"

namespace tiller {
namespace {

struct Rig {
  Rig() : node(std::string(TILLER_SOURCE_DIR) + "/test/mixer/data/t200_pair_mixer.yaml"), ex(0) {
    ex.add(node);
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
      if (ch == channels::kThrusterCommand) {
        ASSERT_EQ(last.decode(d, 0, n), n);
      }
    });
  }
  void stick(double surge, TimeUs at) {
    manual_demand_t m{};
    m.utime = at;
    m.valid = true;
    m.demand[0] = surge;
    ex.inject(channels::kManualDemand, m, at);
  }
  void power(double volts, TimeUs at) {
    power_t p{};
    p.utime = at;
    p.voltage = volts;
    p.current = 5;
    p.power = volts * 5;
    p.monitor = "test";
    ex.inject(channels::kPower, p, at);
  }
  // Drives at `surge` from `from` on, the stick sent every 100 ms, to `to`.
  void drive(double surge, TimeUs from, TimeUs to) {
    for (TimeUs t = from; t <= to; t += 100'000) {
      stick(surge, t);
      ex.run_until(t);
    }
  }
  MixerNode node;
  LockstepExecutor ex;
  thruster_command_t last{};
};

TEST(MixerSupply, TheBatteryVoltageSetsTheCommandForTheSameThrust) {
  Rig r;
  arm_state_t a{};
  a.utime = 0;
  a.armed = true;
  a.session = 1;
  for (TimeUs t = 0; t <= 10'000'000; t += 200'000) {  // armed throughout
    a.utime = t;
    r.ex.inject(channels::kArmState, a, t);
  }
  r.drive(0.0, 0, 200'000);  // centred: the gate opens
  r.drive(0.5, 300'000, 1'000'000);
  ASSERT_EQ(r.last.gate, thruster_command_t::GATE_ACTIVE);
  const double at16 = r.last.command[0];  // no TILLER_POWER yet: the 16 V table
  ThrustCurve c = ThrustCurve::preset("t200");
  const double thrust = c.thrust(at16);    // at 16 V
  EXPECT_NEAR(thrust, 0.5 * 36.38, 0.01);  // half of the surge axis (2 x 36.38 N), per thruster
  r.power(12.0, 1'050'000);
  r.drive(0.5, 1'100'000, 2'000'000);
  const double at12 = r.last.command[0];
  c.set_supply_voltage(12.0);
  EXPECT_GT(at12, at16 + 0.05);
  EXPECT_NEAR(c.thrust(at12), thrust, 1e-6);  // the same thrust
  r.power(14.8, 2'050'000);
  r.drive(0.5, 2'100'000, 2'500'000);
  c.set_supply_voltage(14.8);
  EXPECT_LT(r.last.command[0], at12);
  EXPECT_GT(r.last.command[0], at16);
  EXPECT_NEAR(c.thrust(r.last.command[0]), thrust, 1e-6);
  std::printf("%.2f N per thruster: command %.4f at 16 V, %.4f at 14.8 V, %.4f at 12 V\n", thrust,
              at16, r.last.command[0], at12);
  // A bad sample: refused and counted, the voltage unchanged.
  r.power(std::nan(""), 2'550'000);
  r.drive(0.5, 2'600'000, 3'000'000);
  EXPECT_EQ(r.node.counter_value("rejected.power.invalid"), 1);
  EXPECT_NEAR(c.thrust(r.last.command[0]), thrust, 1e-6);
  // No power for 2 s: back to the 16 V table, counted once.
  r.drive(0.5, 3'100'000, 5'000'000);
  EXPECT_DOUBLE_EQ(r.last.command[0], at16);
  EXPECT_EQ(r.node.counter_value("supply_voltage.stale"), 1);
}

}  // namespace
}  // namespace tiller
