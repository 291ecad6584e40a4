// SimNode: ESC output (both hardware units, reversal, disarm, staleness, bad input) to thrust,
// published rates, determinism by seed, config errors, and the closed loop with the real
// MixerNode and EscNode (sim backend) in lockstep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "core/angles.hpp"
#include "esc/esc_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/sim_node.hpp"

namespace tiller {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

SimParams params_for(const std::string& vehicle) {
  SimParams p;
  p.vehicle_file = kSrc + "/config/vehicles/" + vehicle + ".yaml";
  return p;
}

esc_output_t esc_output(const Vehicle& v, std::int8_t unit, const std::vector<std::int32_t>& values,
                        bool armed = true) {
  esc_output_t m{};
  m.backend = "sim";
  m.armed = armed;
  m.unit = unit;
  m.n_channels = v.size();
  for (int i = 0; i < v.size(); ++i) {
    m.names.push_back(v.thrusters[static_cast<std::size_t>(i)].name);
    m.channel.push_back(i);
    m.value.push_back(values[static_cast<std::size_t>(i)]);
    m.normalized.push_back(0.0);
  }
  return m;
}

// Feeds the same ESC output every 10 ms from `from` to `to` (as tiller-esc's 100 Hz cycle).
void feed(LockstepExecutor& ex, const esc_output_t& m, TimeUs from, TimeUs to) {
  for (TimeUs t = from; t <= to; t += 10'000) {
    esc_output_t c = m;
    c.utime = t;
    ex.inject(channels::kEscOutput, c, t);
  }
}

struct Recorder {
  std::vector<odometry_t> odom, truth;
  std::vector<sim_state_t> state;
  std::vector<Event> all;
  void attach(LockstepExecutor& ex) {
    ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      Event e{ch, t, std::vector<std::uint8_t>(d, d + n)};
      if (ch == channels::kOdometry) decode(e, odom.emplace_back());
      if (ch == channels::kGroundTruth) decode(e, truth.emplace_back());
      if (ch == channels::kSimState) decode(e, state.emplace_back());
      all.push_back(std::move(e));
    });
  }
};

TEST(SimNode, OtterFullThrottleThroughEscOutputReaches3_1MetresPerSecond) {
  const auto p = params_for("otter");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  Recorder rec;
  rec.attach(ex);
  feed(ex, esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767}), 0,
       30 * kUsPerSecond);
  ex.run_until(30 * kUsPerSecond);
  ASSERT_FALSE(rec.odom.empty());
  // 20 Hz odometry, ground truth and state over 30 s, first at t = 0.
  EXPECT_EQ(rec.odom.size(), 601u);
  EXPECT_EQ(rec.truth.size(), 601u);
  EXPECT_EQ(rec.state.size(), 601u);
  EXPECT_EQ(rec.odom[1].utime, 50'000);
  const auto& last = rec.odom.back();
  EXPECT_NEAR(last.velocity[0], 2 * 119.7 / 77.55, 1e-4);  // 3.087 m/s, otter.py ~3.2
  EXPECT_NEAR(last.velocity[0], 3.2, 0.05 * 3.2);
  EXPECT_NEAR(last.position[1], 0.0, 1e-9);
  EXPECT_EQ(rec.state.back().n_thrusters, 2);
  EXPECT_NEAR(rec.state.back().thrust[0], 119.7, 1e-6);
  EXPECT_EQ(node.rejected(), 0);
  EXPECT_TRUE(node.esc_fresh());
}

TEST(SimNode, PulseWidthsDriveTheRovsVerticalThrustersThroughTheT200Curve) {
  const auto p = params_for("seed001_rov6");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  const Vehicle& v = node.vehicle();
  LockstepExecutor ex(0);
  ex.add(node);
  // F and B at 1900 us (full forward = up, their direction is -z), the rest neutral.
  std::vector<std::int32_t> us(static_cast<std::size_t>(v.size()), 1500);
  us[static_cast<std::size_t>(v.index_of("F"))] = 1900;
  us[static_cast<std::size_t>(v.index_of("B"))] = 1900;
  feed(ex, esc_output(v, esc_output_t::UNIT_PULSE_US, us), 0, 30 * kUsPerSecond);
  ex.run_until(30 * kUsPerSecond);
  const double full =
      v.thrusters[static_cast<std::size_t>(v.index_of("F"))].thrust_from_command(1.0);
  EXPECT_NEAR(full, 3.71 * 9.80665, 0.01);  // T200 at 12 V, 1900 us: 3.71 kgf
  EXPECT_NEAR(node.commanded_thrust(v.index_of("F")), full, 1e-9);
  EXPECT_EQ(node.commanded_thrust(v.index_of("LF")), 0.0);  // 1500 us: neutral
  // Rises: 2 * 36.38 N up against 0.98 N of net weight; 33 w + 190 w^2 = 71.8 N.
  const auto& d = node.model().params();
  const double f = 2 * full - (d.weight_n - d.buoyancy_n);
  const double w = (-33.0 + std::sqrt(33.0 * 33.0 + 4 * 190.0 * f)) / (2 * 190.0);
  EXPECT_NEAR(node.model().nu()[2], -w, 1e-5);
  EXPECT_NEAR(w, 0.533, 0.001);
  EXPECT_LT(node.model().eta()[2], -10.0);        // 30 s up at about 0.53 m/s
  EXPECT_NEAR(node.model().eta()[4], 0.0, 1e-6);  // F and B equal: no pitch
}

// Seed 000's motors are T200s: the simulator uses the T200 12 V data (simulator_thrust_curve)
// while the mixer keeps the seed's linear 30 N (test/allocation reproduces its a/b arithmetic).
TEST(SimNode, Seed000FullThrottleGivesTheT200Thrust) {
  const auto p = params_for("seed000_rov4");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  const Vehicle mixer_view = load_vehicle_file(p.vehicle_file);
  EXPECT_EQ(mixer_view.thrusters[0].thrust_from_command(1.0), 30.0);  // the seed's assumption
  node.on_esc_output(
      esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, -32767, 16384, 0}), 0);
  // Blue Robotics' T200 data (docs/adding-a-vehicle.md): at 12 V, 1900 us +3.71 kgf, 1100 us -2.90
  // kgf.
  EXPECT_NEAR(node.commanded_thrust(0), 3.71 * 9.80665, 1e-9);
  EXPECT_NEAR(node.commanded_thrust(1), -2.90 * 9.80665, 1e-9);
  // Half throttle (1700 us): 1.28 kgf, about a third of full, not 15 N.
  EXPECT_NEAR(node.commanded_thrust(2), node.vehicle().thrusters[2].curve.thrust(16384.0 / 32767.0),
              1e-12);
  EXPECT_NEAR(node.commanded_thrust(2), 1.28 * 9.80665, 0.01);
  EXPECT_EQ(node.commanded_thrust(3), 0.0);
  // And the thrust reaches it through the lag.
  LockstepExecutor ex(0);
  ex.add(node);
  feed(ex,
       esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767, 32767, 32767}),
       0, 2 * kUsPerSecond);
  ex.run_until(2 * kUsPerSecond);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(node.model().thrust(i), 36.38, 0.01) << i;
  // A file naming an unknown curve is refused with the key and the known names.
  try {
    const auto v = config::Value::parse(
        "model: underwater_6dof\nthruster_time_constant_s: 0.1\nsimulator_thrust_curve: t300\n",
        "bad.yaml");
    (void)sim::load_dynamics(v);
    FAIL() << "unknown curve accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "simulator_thrust_curve: expected a thrust curve preset "
                  "name (t200_12v, t200_14v8, t200_16v, t200, t200_poly), got 't300'"),
              std::string::npos)
        << e.what();
  }
}

TEST(SimNode, PulseMappingFollowsTheConfiguredEndpoints) {
  auto p = params_for("seed001_rov6");
  p.pulse_min_us = 1000;
  p.pulse_neutral_us = 1500;
  p.pulse_max_us = 1900;
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  double u = 0;
  ASSERT_TRUE(node.motor_command(esc_output_t::UNIT_PULSE_US, 1700, u));
  EXPECT_DOUBLE_EQ(u, 0.5);
  ASSERT_TRUE(node.motor_command(esc_output_t::UNIT_PULSE_US, 1250, u));
  EXPECT_DOUBLE_EQ(u, -0.5);
  ASSERT_TRUE(node.motor_command(esc_output_t::UNIT_PULSE_US, 2100, u));
  EXPECT_DOUBLE_EQ(u, 1.0);  // clamped
  ASSERT_TRUE(node.motor_command(esc_output_t::UNIT_THROTTLE_INT16, -16384, u));
  EXPECT_NEAR(u, -16384.0 / 32767.0, 1e-15);
  EXPECT_FALSE(node.motor_command(esc_output_t::UNIT_PULSE_US, 3000, u));
  EXPECT_FALSE(node.motor_command(esc_output_t::UNIT_THROTTLE_INT16, 40000, u));
  EXPECT_FALSE(node.motor_command(7, 0, u));
}

TEST(SimNode, ReversedThrusterIsFlippedBackAndUsesTheMotorsReverseSide) {
  const auto p = params_for("otter");
  auto sv = load_sim_vehicle_file(p.vehicle_file);
  sv.vehicle.thrusters[0].reversed = true;
  SimNode node(p, sv);
  // Tiller command +1 on the reversed port thruster: tiller-esc sends motor -1 (-32767).
  // Pushing along `direction` then uses the motor's weaker reverse side: +66.7 N.
  node.on_esc_output(esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {-32767, 32767}),
                     0);
  EXPECT_NEAR(node.commanded_thrust(0), 66.7, 1e-9);
  EXPECT_NEAR(node.commanded_thrust(1), 119.7, 1e-9);
  // And motor +1 on it pushes against `direction` with the strong side.
  node.on_esc_output(esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 0}), 0);
  EXPECT_NEAR(node.commanded_thrust(0), -119.7, 1e-9);
}

TEST(SimNode, DisarmedOutputGivesZeroThrust) {
  const auto p = params_for("otter");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  node.on_esc_output(
      esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767}, false), 0);
  EXPECT_EQ(node.commanded_thrust(0), 0.0);
  EXPECT_EQ(node.commanded_thrust(1), 0.0);
  EXPECT_EQ(node.rejected(), 0);
}

TEST(SimNode, StaleEscOutputDecaysTheThrustToZero) {
  auto p = params_for("otter");
  p.esc_timeout_us = 500'000;
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  Recorder rec;
  rec.attach(ex);
  feed(ex, esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767}), 0,
       5 * kUsPerSecond);
  ex.run_until(5 * kUsPerSecond + 500'000);  // last output at 5.0 s, still fresh at 5.5 s
  EXPECT_NEAR(node.model().thrust(0), 119.7, 1e-6);
  EXPECT_TRUE(node.esc_fresh());
  ex.run_until(5 * kUsPerSecond + 510'000);  // stale now: target 0
  EXPECT_FALSE(node.esc_fresh());
  EXPECT_EQ(node.stale(), 1);
  // Thrust decays with the 0.1 s lag from the moment it went stale (the 5.50..5.51 s step
  // already has the zero target): at 5.81 s, e^-3.1 of full.
  ex.run_until(5 * kUsPerSecond + 810'000);
  EXPECT_NEAR(node.model().thrust(0), 119.7 * std::exp(-3.1), 1e-6);
  ex.run_until(20 * kUsPerSecond);
  EXPECT_LT(std::abs(node.model().thrust(0)), 1e-9);
  EXPECT_LT(node.model().nu()[0], 1e-3);
}

// esc_timeout_model: hardware. Seed 000's I2C throttle ESCs (tgy) keep the last throttle for
// 4.5 s and then stop; seed 001's PWM ESCs behind a PCA9685 keep the last pulse for good.
TEST(SimNode, HardwareTimeoutModelHoldsTheLastOutputAsTheEscWould) {
  {
    auto p = params_for("seed000_rov4");
    p.esc_timeout_model = SimParams::EscTimeoutModel::kHardware;
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    LockstepExecutor ex(0);
    ex.add(node);
    feed(ex, esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767, 0, 0}), 0,
         kUsPerSecond);
    ex.run_until(kUsPerSecond + 4'500'000);  // 4.5 s after the last output: still driving
    EXPECT_TRUE(node.esc_fresh());
    EXPECT_NEAR(node.model().thrust(0), 36.38, 0.01);
    ex.run_until(kUsPerSecond + 4'510'000);
    EXPECT_FALSE(node.esc_fresh());
    ex.run_until(kUsPerSecond + 6'000'000);
    EXPECT_LT(std::abs(node.model().thrust(0)), 1e-9);
  }
  {
    auto p = params_for("seed001_rov6");
    p.esc_timeout_model = SimParams::EscTimeoutModel::kHardware;
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    LockstepExecutor ex(0);
    ex.add(node);
    std::vector<std::int32_t> us(6, 1500);
    us[1] = 1700;
    feed(ex, esc_output(node.vehicle(), esc_output_t::UNIT_PULSE_US, us), 0, kUsPerSecond);
    ex.run_until(120 * kUsPerSecond);  // two minutes without a message
    EXPECT_TRUE(node.esc_fresh());
    EXPECT_NEAR(node.model().thrust(1), node.vehicle().thrusters[1].thrust_from_command(0.5), 1e-9);
    EXPECT_EQ(node.stale(), 0);
  }
  // The shipped config keeps the safe default; a bad value names the key.
  const auto root = config::Value::load_file(kSrc + "/config/sim/sim.yaml");
  EXPECT_EQ(load_sim_params(root).esc_timeout_model, SimParams::EscTimeoutModel::kSafe);
  try {
    const auto v = config::Value::parse(
        "vehicle: ../vehicles/otter.yaml\nodometry_rate_hz: 20\nground_truth_rate_hz: 20\n"
        "sim_state_rate_hz: 20\nesc_timeout_s: 0.5\nesc_timeout_model: real\n",
        kSrc + "/config/sim/test.yaml");
    (void)load_sim_params(v);
    FAIL() << "esc_timeout_model: real accepted";
  } catch (const config::Error& e) {
    EXPECT_NE(std::string(e.what()).find("esc_timeout_model"), std::string::npos) << e.what();
  }
}

TEST(SimNode, BadEscOutputIsDroppedAndCountedAndTheLastGoodOneStays) {
  const auto p = params_for("otter");
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  const Vehicle& v = node.vehicle();
  node.on_esc_output(esc_output(v, esc_output_t::UNIT_THROTTLE_INT16, {16384, 16384}), 0);
  const double good = node.commanded_thrust(0);
  EXPECT_GT(good, 0.0);
  auto unknown = esc_output(v, esc_output_t::UNIT_THROTTLE_INT16, {32767, 32767});
  unknown.names[1] = "bow";
  node.on_esc_output(unknown, 1);
  node.on_esc_output(esc_output(v, 9, {32767, 32767}), 2);
  node.on_esc_output(esc_output(v, esc_output_t::UNIT_THROTTLE_INT16, {32767, 99999}), 3);
  node.on_esc_output(esc_output(v, esc_output_t::UNIT_PULSE_US, {1500, 100}), 4);
  auto too_many = esc_output(v, esc_output_t::UNIT_THROTTLE_INT16, {0, 0});
  too_many.n_channels = 3;  // arrays disagree with the count
  node.on_esc_output(too_many, 5);
  EXPECT_EQ(node.commanded_thrust(0), good);
  EXPECT_EQ(node.rejected(), 5);
  EXPECT_EQ(node.counter_value("rejected.esc_output.unknown_thruster"), 1);
  EXPECT_EQ(node.counter_value("rejected.esc_output.unit"), 1);
  EXPECT_EQ(node.counter_value("rejected.esc_output.out_of_range"), 2);
  EXPECT_EQ(node.counter_value("rejected.esc_output.n_channels"), 1);
  // Malformed bytes are counted by the runtime and do not reach the handler.
  std::uint8_t junk[7] = {1, 2, 3, 4, 5, 6, 7};
  node.deliver(channels::kEscOutput, junk, sizeof junk, 6);
  EXPECT_EQ(node.counter_value(std::string("malformed.") + channels::kEscOutput), 1);
  EXPECT_EQ(node.commanded_thrust(0), good);
}

std::vector<Event> seeded_run(std::uint64_t seed) {
  auto p = params_for("seed004_usv_x");
  p.seed = seed;
  p.current.model = sim::CurrentParams::Model::kGaussMarkov;
  p.current.speed_m_s = 0.3;
  p.current.toward_rad = deg_to_rad(30);
  p.current.mu_per_s = 0.1;
  p.current.speed_std_m_s = 0.1;
  p.current.direction_std_rad = deg_to_rad(20);
  p.current.speed_max_m_s = 0.6;
  p.noise.position_std_m = 0.5;
  p.noise.orientation_std_rad = deg_to_rad(2);
  p.noise.linear_velocity_std_m_s = 0.05;
  p.noise.angular_velocity_std_rad_s = deg_to_rad(1);
  SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(node);
  Recorder rec;
  rec.attach(ex);
  feed(ex,
       esc_output(node.vehicle(), esc_output_t::UNIT_THROTTLE_INT16, {20000, 20000, 10000, 10000}),
       0, 20 * kUsPerSecond);
  ex.run_until(20 * kUsPerSecond);
  // Noise reaches odometry, never ground truth, and stays in the surface vessel's DOFs.
  const auto& o = rec.odom.back();
  const auto& t = rec.truth.back();
  EXPECT_NE(o.position[0], t.position[0]);
  EXPECT_EQ(o.position[2], 0.0);
  EXPECT_EQ(o.orientation[0], 0.0);
  EXPECT_EQ(t.position[2], 0.0);
  return rec.all;
}

TEST(SimNode, SameSeedSameRunBitForBit) {
  const auto a = seeded_run(42);
  const auto b = seeded_run(42);
  const auto c = seeded_run(43);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].channel, b[i].channel);
    ASSERT_EQ(a[i].time, b[i].time);
    ASSERT_EQ(a[i].data, b[i].data) << "event " << i;
  }
  bool differs = false;
  for (std::size_t i = 0; i < a.size() && i < c.size(); ++i)
    differs = differs || a[i].data != c[i].data;
  EXPECT_TRUE(differs);
}

TEST(SimNode, ConfigFileLoadsAndBadConfigsNameTheKey) {
  const auto root = config::Value::load_file(kSrc + "/config/sim/sim.yaml");
  const auto p = load_sim_params(root);
  root.check_all_used();
  EXPECT_EQ(p.step_us, 10'000);
  EXPECT_EQ(p.odometry_period_us, 50'000);
  EXPECT_EQ(load_sim_vehicle_file(p.vehicle_file).vehicle.name, "seed004_usv_x");
  auto expect_error = [](const std::string& yaml, const std::string& fragment) {
    try {
      const auto v = config::Value::parse(yaml, kSrc + "/config/sim/test.yaml");
      (void)load_sim_params(v);
      v.check_all_used();
      FAIL() << "no error for " << yaml;
    } catch (const config::Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  const std::string base =
      "vehicle: ../vehicles/otter.yaml\nodometry_rate_hz: 20\nground_truth_rate_hz: 20\n"
      "sim_state_rate_hz: 20\nesc_timeout_s: 0.5\n";
  expect_error(base + "typo: 1\n", "typo");
  expect_error("vehicle: ../vehicles/nope.yaml\nodometry_rate_hz: 20\n", "vehicle");
  expect_error(
      "vehicle: ../vehicles/otter.yaml\nodometry_rate_hz: 30\nground_truth_rate_hz: 20\n"
      "sim_state_rate_hz: 20\nesc_timeout_s: 0.5\n",
      "odometry_rate_hz");
  expect_error(base + "current: {model: constant, speed_m_s: 0.3, toward: 30}\n", "toward_deg");
  expect_error(base + "pulse_us: {min: 1600, neutral: 1500, max: 1900}\n", "pulse_us");
  // RK4 at <= 10 ms (docs/adding-a-vehicle.md); a longer step is refused naming the key and the
  // range.
  expect_error(base + "step_s: 0.02\n", "step_s: expected a number in [0.0001, 0.01]");
  // With model none the other keys are still checked: a typo, or a bad value, is refused.
  expect_error(base + "current: {model: none, speed_m_s: 0.3, towards_deg: 30}\n", "towards_deg");
  expect_error(base + "current: {model: none, speed_m_s: -1}\n", "speed_m_s");
  expect_error(base + "current: {model: constant, speed_m_s: 0.3}\n", "toward_deg");
  expect_error(base +
                   "current: {model: gauss_markov, speed_m_s: 0.5, toward_deg: 0, mu_per_s: 0.01, "
                   "speed_std_m_s: 0.05, direction_std_deg: 10, speed_max_m_s: 0.2}\n",
               "speed_max_m_s");
  // The shipped file lists every key with model none; switching the model needs no other edit.
  for (const char* m : {"constant", "gauss_markov"}) {
    const auto v = config::Value::parse(base + "current: {model: " + m +
                                            ", speed_m_s: 0.3, toward_deg: 30, mu_per_s: 0.01, "
                                            "speed_std_m_s: 0.05, direction_std_deg: 10, "
                                            "speed_max_m_s: 0.6}\n",
                                        kSrc + "/config/sim/test.yaml");
    const auto q = load_sim_params(v);
    EXPECT_NO_THROW(v.check_all_used()) << m;
    EXPECT_EQ(q.current.speed_m_s, 0.3);
    EXPECT_EQ(q.current.speed_max_m_s, std::string(m) == "constant" ? 0.3 : 0.6);
  }
  // Every shipped vehicle file (all of config/vehicles/, so a new one is covered) has a
  // dynamics section the simulator accepts.
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(kSrc + "/config/vehicles")) {
    if (e.path().extension() != ".yaml") continue;
    ++n;
    EXPECT_NO_THROW(load_sim_vehicle_file(e.path().string())) << e.path();
  }
  EXPECT_GE(n, 7);
}

TEST(SimNode, WindOnAnUnderwaterVehicleIsRefusedNamingTheKey) {
  const std::string base =
      "vehicle: ../vehicles/seed001_rov6.yaml\nodometry_rate_hz: 20\nground_truth_rate_hz: 20\n"
      "sim_state_rate_hz: 20\nesc_timeout_s: 0.5\nwind: {enabled: true, speed_m_s: 5}\n";
  const auto v = config::Value::parse(base, kSrc + "/config/sim/wind.yaml");
  const auto p = load_sim_params(v);
  v.check_all_used();
  try {
    SimNode node(p, load_sim_vehicle_file(p.vehicle_file));
    FAIL() << "wind accepted on an underwater vehicle";
  } catch (const config::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("config/sim/wind.yaml:6: wind.enabled: expected false"), std::string::npos)
        << what;
    EXPECT_NE(what.find("underwater_6dof"), std::string::npos) << what;
  }
  // The same config on a surface vessel with wind coefficients runs; wind off runs anywhere.
  auto q = p;
  q.vehicle_file = kSrc + "/config/vehicles/wamv.yaml";
  EXPECT_NO_THROW(SimNode(q, load_sim_vehicle_file(q.vehicle_file)));
  q = p;
  q.wind_enabled = false;
  EXPECT_NO_THROW(SimNode(q, load_sim_vehicle_file(q.vehicle_file)));
}

TEST(SimNode, NonFiniteOrNegativeStartValuesAreRefused) {
  auto p = params_for("otter");
  const auto v = load_sim_vehicle_file(p.vehicle_file);
  p.initial_eta[0] = INFINITY;
  EXPECT_THROW(SimNode(p, v), std::invalid_argument);
  p = params_for("otter");
  p.initial_eta[5] = NAN;
  EXPECT_THROW(SimNode(p, v), std::invalid_argument);
  p = params_for("otter");
  p.current.model = sim::CurrentParams::Model::kConstant;
  p.current.speed_m_s = -1;  // a southward current in disguise, and clamp(x, 0, -1) is UB
  p.current.speed_max_m_s = -1;
  EXPECT_THROW(SimNode(p, v), std::invalid_argument);
}

// The whole chain in one process: manual demand -> MixerNode -> EscNode (sim backend) ->
// SimNode -> odometry. Full forward demand on the Otter must give its top speed.
TEST(SimNode, ClosedLoopWithMixerAndEscInLockstep) {
  MixerNode mixer(kSrc + "/config/mixer/otter.yaml");
  EscNode esc(kSrc + "/config/esc/otter_sim.yaml");
  const auto p = params_for("otter");
  SimNode sim(p, load_sim_vehicle_file(p.vehicle_file));
  LockstepExecutor ex(0);
  ex.add(sim);
  ex.add(mixer);
  ex.add(esc);
  arm_request_t arm{};
  arm.arm = true;
  arm.source = "test";
  ex.inject(channels::kArmRequest, arm, 100'000);
  for (TimeUs t = 200'000; t <= 40 * kUsPerSecond; t += 100'000) {
    manual_demand_t d{};
    d.utime = t;
    d.valid = true;
    // Centred first (the mixer's intent gate holds neutral until the pilot shows neutral after
    // arming, docs/safety.md), then full ahead.
    d.demand[0] = t < 500'000 ? 0.0 : 1.0;
    ex.inject(channels::kManualDemand, d, t);
  }
  ex.run_until(40 * kUsPerSecond);
  EXPECT_TRUE(esc.armed());
  EXPECT_TRUE(sim.esc_fresh());
  EXPECT_NEAR(sim.model().nu()[0], 2 * 119.7 / 77.55, 0.01 * 3.087);
  EXPECT_NEAR(sim.model().eta()[1], 0.0, 1e-6);
  EXPECT_EQ(sim.rejected(), 0);
}

// A pilot's full demand on one axis at a time through the real mixer and ESC (sim backend):
// the seed ROVs move the way they are pushed and never capsize (roll and pitch stay within
// 35 degrees, about 20 degrees steady, as the vehicle files' dynamics notes say). Seed 001's
// pitch axis (F up, B down) pitches the nose up against the CB's righting moment; there the
// pitch is the point, so only roll is bounded and the pitch must pass 10 degrees without
// reaching 90; the BlueROV2-class vehicle's roll axis (VL up, VR down) likewise.
TEST(SimNode, RovsFlyEveryAxisFromFullDemandWithoutCapsizing) {
  struct Case {
    const char* vehicle;
    const char* esc;
    std::vector<int> axes;
    double max_tilt_deg = 35;
  };
  const Case cases[] = {{"seed001_rov6", "seed001_sim", {0, 1, 2, 4, 5}, 35},
                        {"seed000_rov4", "seed000_sim", {0, 1, 5}, 35},
                        // Full surge from rest: 17.7 deg steady, a 35.4 deg peak as the thrust
                        // steps in (50 ms lag) against the small pitch damping (Mq 0.8).
                        {"bluerov2", "bluerov2_sim", {0, 1, 2, 3, 5}, 40}};
  for (const auto& c : cases) {
    for (int axis : c.axes) {
      MixerNode mixer(kSrc + "/config/mixer/" + c.vehicle + ".yaml");
      EscNode esc(kSrc + "/config/esc/" + c.esc + ".yaml");
      const auto p = params_for(c.vehicle);
      SimNode sim(p, load_sim_vehicle_file(p.vehicle_file));
      LockstepExecutor ex(0);
      ex.add(sim);
      ex.add(mixer);
      ex.add(esc);
      arm_request_t arm{};
      arm.arm = true;
      arm.source = "test";
      ex.inject(channels::kArmRequest, arm, 100'000);
      for (TimeUs t = 200'000; t <= 20 * kUsPerSecond; t += 100'000) {
        manual_demand_t d{};
        d.utime = t;
        d.valid = true;
        d.demand[axis] = t < 500'000 ? 0.0 : 1.0;  // centred first: the intent gate
        ex.inject(channels::kManualDemand, d, t);
      }
      double max_tilt = 0, max_pitch = 0, max_roll = 0;
      for (TimeUs t = 0; t <= 20 * kUsPerSecond; t += 50'000) {
        ex.run_until(t);
        const auto& eta = sim.model().eta();
        max_pitch = std::max(max_pitch, std::abs(eta[4]));
        max_roll = std::max(max_roll, std::abs(eta[3]));
        max_tilt = std::max(
            {max_tilt, axis == 3 ? 0.0 : std::abs(eta[3]), axis == 4 ? 0.0 : std::abs(eta[4])});
      }
      SCOPED_TRACE(std::string(c.vehicle) + " axis " + std::to_string(axis));
      EXPECT_TRUE(esc.armed());
      EXPECT_LT(max_tilt, deg_to_rad(c.max_tilt_deg));
      const auto& nu = sim.model().nu();
      if (axis < 3) {
        EXPECT_GT(nu[axis], 0.3);  // m/s along the demanded axis
      } else if (axis == 3) {
        EXPECT_GT(sim.model().eta()[3], deg_to_rad(10));  // rolled right, held there
        EXPECT_LT(max_roll, deg_to_rad(89));
        EXPECT_LT(sim.model().nu().head<3>().norm(), 0.1);  // rolls in place
      } else if (axis == 4) {
        EXPECT_GT(sim.model().eta()[4], deg_to_rad(10));  // nose up, held there
        EXPECT_LT(max_pitch, deg_to_rad(89));
        EXPECT_LT(sim.model().nu().head<3>().norm(), 0.1);  // pitches in place
      } else {
        EXPECT_GT(nu[5], 1.0);  // rad/s, yawing clockwise
      }
    }
  }
}

}  // namespace
}  // namespace tiller
