// The simulated battery under the simulated vehicles' full thrust (issue 14 item 6: the levels of
// config/failsafe/otter_sim.yaml and rov_sim.yaml). Every thruster at 1900 us (full forward)
// through SimNode with the simulated sensors for 3 s; TILLER_POWER's voltage against the closed
// form of lib/sim/sensor_models.hpp (V = E - I R, P = V I, capped at the maximum power E^2/4R).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <tiller/esc_output_t.hpp>
#include <tiller/power_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/sensor_suite.hpp"
#include "sim/sim_node.hpp"

namespace tiller::sim {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

struct Sag {
  double min_v = 1e9, at_a = 0;
};

// Every thruster at full forward for 3 s; the lowest voltage from 1 s on (the thrust has risen).
Sag full_thrust(const std::string& vehicle, const std::string& sensors) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/" + vehicle + ".yaml";
  p.sensors = load_sensor_file(kSrc + "/config/sim/sensors/" + sensors + ".yaml", p.step_us);
  p.sensors.power.voltage_std_v = 0;  // the model's voltage, without the monitor's noise
  p.sensors.power.current_std_a = 0;
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  Sag sag;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    power_t m;
    if (ch == channels::kPower && m.decode(d, 0, n) == n && t >= kUsPerSecond &&
        m.voltage < sag.min_v) {
      sag.min_v = m.voltage;
      sag.at_a = m.current;
    }
  });
  const auto& v = node.vehicle();
  esc_output_t m{};
  m.backend = "sim";
  m.armed = true;
  m.unit = esc_output_t::UNIT_PULSE_US;
  m.n_channels = v.size();
  for (int i = 0; i < v.size(); ++i) {
    m.names.push_back(v.thrusters[static_cast<std::size_t>(i)].name);
    m.channel.push_back(i);
    m.value.push_back(1900);
    m.normalized.push_back(1.0);
  }
  for (TimeUs t = 0; t <= 3 * kUsPerSecond; t += 10'000) {
    m.utime = t;
    ex.inject(channels::kEscOutput, m, t);
  }
  ex.run_until(3 * kUsPerSecond);
  return sag;
}

// The closed form: the bus voltage for a load of `w` W from 16.8 V behind 0.03 ohm.
double closed_form_v(double w) {
  const double e = 16.8, r = 0.03, disc = e * e - 4 * r * w;
  const double i = disc > 0 ? (e - std::sqrt(disc)) / (2 * r) : e / (2 * r);
  return e - i * r;
}

TEST(BatterySag, TheOttersFullThrustCollapsesTheSimulatedFourCellPack) {
  const Sag s = full_thrust("otter", "usv");
  // 15 W + 2 x 1.1 x 119.7^1.5 = 2896 W > E^2 / 4R = 2352 W: the most the pack gives, at E / 2.
  const double w = 15 + 2 * 1.1 * std::pow(119.7, 1.5);
  EXPECT_NEAR(w, 2896, 1);
  EXPECT_NEAR(closed_form_v(w), 8.4, 1e-9);
  EXPECT_NEAR(s.min_v, 8.4, 0.05);  // the open-circuit voltage falls 0.2 V/Ah meanwhile
  EXPECT_NEAR(s.at_a, 280, 2);
  std::printf("Otter, 2 x 119.7 N: %.2f V at %.0f A (warn 14.0, critical 13.2)\n", s.min_v, s.at_a);
}

TEST(BatterySag, TheRovsFullThrustStaysAboveTheCriticalLevel) {
  const Sag s = full_thrust("bluerov2", "rov");
  const double w = 20 + 6 * 1.1 * std::pow(36.38, 1.5);  // 1468 W
  EXPECT_NEAR(closed_form_v(w), 13.55, 0.01);
  EXPECT_NEAR(s.min_v, closed_form_v(w), 0.05);
  EXPECT_GT(s.min_v, 13.2 + 0.2);  // rov_sim.yaml's critical level and its hysteresis
  EXPECT_LT(s.min_v, 14.0);  // ... but under its warning level (rov_sim.yaml compensates the sag)
  std::printf("BlueROV2, 6 x 36.38 N: %.2f V at %.0f A\n", s.min_v, s.at_a);
}

}  // namespace
}  // namespace tiller::sim
