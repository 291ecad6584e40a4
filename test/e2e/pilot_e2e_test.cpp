// End to end, real processes over LCM in a private network namespace (tools/netns-run):
//   FIFO (in place of /dev/input/js0) -> tiller-teleop -> tiller-mixer (seed 000's ROV)
//   -> tiller-esc (sim backend: publishes what it would put on the I2C bus) -> this test.
// Checks: the ESCs stay neutral and disarmed until armed from the stick's arm button; known
// stick positions give the throttles seed 000 asks for (hand computed below); closing the FIFO
// writer ("pulling the stick") brings every throttle to 0 within 100 ms (the number);
// the teleop's heartbeat says the stick is absent; after replugging with the stick held
// deflected, nothing moves until the stick has been centred.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <functional>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "e2e_config.hpp"
#include "e2e_util.hpp"

namespace tiller::e2e {
namespace {

struct Rx {
  void on_esc(const lcm::ReceiveBuffer*, const std::string&, const esc_output_t* m) {
    esc = *m;
    esc_time = realtime_us();
    ++n_esc;
    if (on_esc_cb) on_esc_cb(*m, esc_time);
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) { arm = *m; }
  void on_demand(const lcm::ReceiveBuffer*, const std::string&, const manual_demand_t* m) {
    demand = *m;
    ++n_demand;
  }
  void on_hb(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) {
    teleop_hb = *m;
  }
  esc_output_t esc{};
  std::int64_t esc_time = 0;
  int n_esc = 0, n_demand = 0;
  arm_state_t arm{};
  manual_demand_t demand{};
  heartbeat_t teleop_hb{};
  std::function<void(const esc_output_t&, std::int64_t)> on_esc_cb;
};

bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds) {
  const std::int64_t end = realtime_us() + static_cast<std::int64_t>(seconds * 1e6);
  while (realtime_us() < end) {
    if (pred()) return true;
    l.handleTimeout(5);
  }
  return pred();
}

// Throttle of thruster `name` in the last ESC output (or a huge value if absent).
int throttle(const esc_output_t& m, const std::string& name) {
  for (int i = 0; i < m.n_channels; ++i) {
    if (m.names[static_cast<std::size_t>(i)] == name) return m.value[static_cast<std::size_t>(i)];
  }
  return 1 << 30;
}

bool throttles_are(const esc_output_t& m, const std::vector<int>& expected, int tol = 2) {
  if (m.n_channels != static_cast<int>(expected.size())) return false;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::abs(throttle(m, "t" + std::to_string(i + 1)) - expected[i]) > tol) return false;
  }
  return true;
}

bool all_zero(const esc_output_t& m) {
  for (int v : m.value) {
    if (v != 0) return false;
  }
  return m.n_channels > 0;
}

std::string describe(const esc_output_t& m) {
  std::string s = m.armed ? "armed:" : "disarmed:";
  for (int i = 0; i < m.n_channels; ++i) {
    s += " " + m.names[static_cast<std::size_t>(i)] + "=" +
         std::to_string(m.value[static_cast<std::size_t>(i)]);
  }
  return s;
}

TEST(PilotEndToEnd, StickArmsAndDrivesTheEscsAndUnplugStopsThem) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "LCM not available: run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_ESC_OUTPUT", &Rx::on_esc, &rx);
  l.subscribe("TILLER_ARM_STATE", &Rx::on_arm, &rx);
  l.subscribe("TILLER_MANUAL_DEMAND", &Rx::on_demand, &rx);
  l.subscribe("TILLER_HEARTBEAT_TELEOP", &Rx::on_hb, &rx);

  FifoStick stick("/tmp/tiller_e2e_js_" + std::to_string(getpid()));
  const std::string src = TILLER_SOURCE_DIR;
  Proc esc(std::string(TILLER_BIN_DIR) + "/tiller-esc",
           {"--config", src + "/" + kEscConfig, "--lcm-url", kUrl});
  Proc mixer(std::string(TILLER_BIN_DIR) + "/tiller-mixer",
             {"--config", src + "/" + kMixerConfig, "--lcm-url", kUrl});
  Proc teleop(std::string(TILLER_BIN_DIR) + "/tiller-teleop",
              {"--config", src + "/config/teleop/extreme3dpro_seed000.yaml", "--device",
               stick.path(), "--lcm-url", kUrl});

  // Before the stick is plugged in: neutral, disarmed, and the teleop says the stick is absent.
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.n_esc > 5 && rx.teleop_hb.utime != 0; }, 5.0))
      << "no ESC output / teleop heartbeat";
  EXPECT_TRUE(all_zero(rx.esc)) << describe(rx.esc);
  EXPECT_FALSE(rx.esc.armed);
  EXPECT_EQ(rx.teleop_hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(rx.teleop_hb.status.find("joystick absent"), std::string::npos) << rx.teleop_hb.status;

  // Plug in, centred (Extreme 3D Pro at rest: slider at +32767, not mapped).
  stick.plug();
  stick.init({0, 0, 0, 32767, 0, 0});
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.valid; }, 3.0))
      << "teleop never saw the stick";

  // Full forward while disarmed: still nothing on the bus.
  stick.axis(1, -32767);
  pump_until(
      l, [] { return false; }, 0.3);
  EXPECT_TRUE(all_zero(rx.esc)) << describe(rx.esc);
  EXPECT_FALSE(rx.arm.armed);
  // The ESC refuses to arm while the command is not neutral: centre first, then arm.
  stick.axis(1, 0);
  pump_until(
      l, [] { return false; }, 0.2);
  stick.button(6, true);  // arm (base button 7), held 100 ms: past the 30 ms debounce
  sleep_ms(100);
  stick.button(6, false);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.arm.armed && rx.esc.armed; }, 3.0))
      << "not armed: " << rx.arm.reason;

  // Known positions -> throttles. Seed 000's ROV (config/vehicles/seed000_rov4.yaml): t1 front
  // left pushing forward-right... each thruster pushes along its `direction` for a positive
  // command; linear, symmetric thrust, int16 throttle = command * 32767.
  //   full forward  J = (1, 0): t1 +, t2 +, t3 -, t4 - all full (the force lies along J and the
  //                 stronger pair is at full: seed 000's two conditions at 45 degrees: a = b = 1)
  //   full right    J = (0, 1): t1 -, t2 +, t3 +, t4 -
  //   corner        J = (1, 1): along t2's direction: t2 +, t4 - full, t1 = t3 = 0
  struct Case {
    const char* what;
    int x, y;
    std::vector<int> expected;
  };
  const int F = 32767;
  const std::vector<Case> cases = {
      {"full forward", 0, -32767, {F, F, -F, -F}},
      {"full right", 32767, 0, {-F, F, F, -F}},
      {"forward-right corner", 32767, -32767, {0, F, 0, -F}},
      {"full back", 0, 32767, {-F, -F, F, F}},
      {"centre", 0, 0, {0, 0, 0, 0}},
  };
  for (const Case& c : cases) {
    stick.write({JsEvent{0, static_cast<std::int16_t>(c.x), kJsEventAxis, 0},
                 JsEvent{0, static_cast<std::int16_t>(c.y), kJsEventAxis, 1}});
    EXPECT_TRUE(pump_until(
        l, [&] { return throttles_are(rx.esc, c.expected); }, 2.0))
        << c.what << ": " << describe(rx.esc);
  }

  // Hold full forward, then pull the plug: every throttle to 0 within 100 ms.
  stick.axis(1, -32767);
  ASSERT_TRUE(pump_until(
      l, [&] { return throttles_are(rx.esc, cases[0].expected); }, 2.0));
  pump_until(
      l, [] { return false; }, 0.1);
  std::int64_t first_zero = 0;
  std::int64_t pulled = 0;
  rx.on_esc_cb = [&](const esc_output_t& m, std::int64_t t) {
    if (pulled != 0 && first_zero == 0 && all_zero(m)) first_zero = t;
  };
  pulled = realtime_us();
  stick.unplug();
  ASSERT_TRUE(pump_until(
      l, [&] { return first_zero != 0; }, 2.0))
      << describe(rx.esc);
  const double ms_to_zero = static_cast<double>(first_zero - pulled) / 1000.0;
  std::printf("unplug -> all throttles 0 after %.2f ms\n", ms_to_zero);
  EXPECT_LT(ms_to_zero, 100.0);
  EXPECT_FALSE(rx.demand.valid);
  rx.on_esc_cb = nullptr;
  // They stay at 0, and the heartbeat says why.
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.teleop_hb.state == heartbeat_t::STATE_DEGRADED; }, 2.5));
  EXPECT_NE(rx.teleop_hb.status.find("joystick absent"), std::string::npos) << rx.teleop_hb.status;
  EXPECT_TRUE(all_zero(rx.esc)) << describe(rx.esc);

  // Replug with the stick held full forward: no jump, still 0 after half a second.
  stick.plug();
  stick.init({0, -32767, 0, 32767, 0, 0});
  int nonzero = 0;
  rx.on_esc_cb = [&](const esc_output_t& m, std::int64_t) { nonzero += all_zero(m) ? 0 : 1; };
  pump_until(
      l, [] { return false; }, 0.5);
  EXPECT_EQ(nonzero, 0) << "thrust before the stick was centred";
  rx.on_esc_cb = nullptr;
  EXPECT_FALSE(rx.demand.valid);
  // Centre, then forward: flying again (re-arming if the ESC disarmed meanwhile).
  stick.axis(1, 0);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.valid; }, 2.0));
  if (!rx.arm.armed) {
    stick.button(6, true);
    sleep_ms(100);
    stick.button(6, false);
    ASSERT_TRUE(pump_until(
        l, [&] { return rx.arm.armed; }, 3.0));
  }
  stick.axis(1, -32767);
  EXPECT_TRUE(pump_until(
      l, [&] { return throttles_are(rx.esc, cases[0].expected); }, 2.0))
      << describe(rx.esc);

  // Disarm from the thumb button: neutral.
  stick.button(1, true);
  sleep_ms(100);
  stick.button(1, false);
  EXPECT_TRUE(pump_until(
      l, [&] { return !rx.arm.armed && all_zero(rx.esc); }, 2.0))
      << describe(rx.esc);

  EXPECT_TRUE(teleop.running());
  EXPECT_TRUE(mixer.running());
  EXPECT_TRUE(esc.running());
  EXPECT_EQ(teleop.stop(), 0);
}

}  // namespace
}  // namespace tiller::e2e
