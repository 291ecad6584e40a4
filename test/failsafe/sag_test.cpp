// The battery rule on the sag-compensated voltage (battery.resistance_ohm): tiller-failsafe's node
// compares V + I R, the pack's resting voltage, so full thrust's sag is not a low battery while a
// drained pack still is. The numbers are the simulated Otter's (config/failsafe/otter_sim.yaml on
// config/sim/sensors/usv.yaml: 16.8 V full, 13.2 V empty, 0.03 ohm): full thrust from a full pack
// reads 8.4 V at 280 A (battery_sag_test), whose resting voltage is 8.4 + 280 x 0.03 = 16.8 V.
#include <gtest/gtest.h>

#include <string>

#include <tiller/power_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include "core/config.hpp"
#include "failsafe/failsafe_config.hpp"
#include "failsafe/failsafe_node.hpp"

namespace tiller::failsafe {
namespace {

// `seconds` of readings (v, i) at 10 Hz from `t0`; returns the status after the last tick.
vehicle_status_t feed(FailsafeNode& n, double t0, double seconds, double v, double i) {
  for (TimeUs t = from_seconds(t0); t <= from_seconds(t0 + seconds); t += 100'000) {
    power_t m{};
    m.utime = t;
    m.voltage = v;
    m.current = i;
    m.power = v * i;
    m.monitor = "test";
    n.on_power(m, t);
    n.on_tick(t);
  }
  return n.last_status();
}

FailsafeNodeParams params(double resistance) {
  return load_failsafe_params(config::Value::parse(
      "battery: {warn_v: 14.0, critical_v: 13.2, trigger_s: 2, resistance_ohm: " +
          std::to_string(resistance) + "}\n",
      "failsafe.yaml"));
}

TEST(BatterySag, FullThrustIsNotALowBatteryWithTheResistanceButADrainedPackIs) {
  FailsafeNode compensated(params(0.03));
  // Full thrust for 10 s from a full pack: 8.4 V at 280 A, resting 16.8 V: nothing.
  EXPECT_EQ(feed(compensated, 0, 10, 8.4, 280).latched, 0);
  // The pack near empty, cruising: 12.6 V at 20 A, resting 13.2 - 0.01: critical after 2 s.
  const auto s = feed(compensated, 10, 3, 12.59, 20);
  EXPECT_EQ(s.latched, 3);  // EVENT_BATTERY_WARN (1) | EVENT_BATTERY_CRITICAL (2)
  EXPECT_NE(s.reason.find("13.19 V < 13.20 V"), std::string::npos) << s.reason;
  // Without the resistance (the bus voltage as read) the same full-thrust burst is critical.
  FailsafeNode raw(params(0));
  EXPECT_NE(feed(raw, 0, 10, 8.4, 280).latched & vehicle_status_t::EVENT_BATTERY_CRITICAL, 0);
}

TEST(BatterySag, ResistanceIsCheckedByTheLoader) {
  try {
    load_failsafe_params(config::Value::parse(
        "battery: {warn_v: 14, critical_v: 13, resistance_ohm: 2}\n", "failsafe.yaml"));
    FAIL() << "a 2 ohm pack was taken";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("battery.resistance_ohm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tiller::failsafe
