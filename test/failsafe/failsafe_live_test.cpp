// The failsafe through LCM with the real processes, in a private network namespace
// (tools/netns-run): tiller-failsafe, tiller-mixer and tiller-esc (sim backend) for seed 001's
// ROV; this test is the pilot (arm request, manual demand pushing down) and the sensors (power
// and leak on the drivers' channels). A wet probe: the next thruster command has both vertical
// thrusters at full up-thrust (measured: the time from the leak message to that command); then
// the battery below critical with trigger_s 0.5 and disarm_after_s 1: disarmed (measured).
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include "e2e_util.hpp"
#include "runtime/channels.hpp"

namespace tiller::e2e {
namespace {

struct Rx {
  void on_cmd(const lcm::ReceiveBuffer*, const std::string&, const thruster_command_t* m) {
    cmd = *m;
    cmd_at = realtime_us();
    if (on_cmd_cb) on_cmd_cb(*m, cmd_at);
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) {
    arm = *m;
    if (!m->armed && armed_once && disarmed_at < 0) disarmed_at = realtime_us();
    armed_once = armed_once || m->armed;
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const vehicle_status_t* m) {
    status = *m;
  }
  thruster_command_t cmd{};
  std::int64_t cmd_at = 0;
  arm_state_t arm{};
  bool armed_once = false;
  std::int64_t disarmed_at = -1;
  vehicle_status_t status{};
  std::function<void(const thruster_command_t&, std::int64_t)> on_cmd_cb;
};

TEST(FailsafeLive, LeakSurfacesAtOnceAndACriticalBatteryDisarms) {
  const std::string src = TILLER_SOURCE_DIR, bin = TILLER_BIN_DIR;
  const std::string cfg = "/tmp/tiller-failsafe-live-" + std::to_string(getpid()) + ".yaml";
  {
    std::ofstream f(cfg);
    f << "battery: {warn_v: 14.0, critical_v: 13.2, trigger_s: 0.5, critical_action: surface, "
         "disarm_after_s: 1.0}\nleak: {action: surface}\n";
  }
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good());
  Rx rx;
  l.subscribe(channels::kThrusterCommand, &Rx::on_cmd, &rx);
  l.subscribe(channels::kArmState, &Rx::on_arm, &rx);
  l.subscribe(channels::kVehicleStatus, &Rx::on_status, &rx);
  Proc esc(bin + "/tiller-esc",
           {"--config", src + "/config/esc/seed001_sim.yaml", "--lcm-url", kUrl});
  Proc mixer(bin + "/tiller-mixer",
             {"--config", src + "/config/mixer/seed001_rov6.yaml", "--lcm-url", kUrl});
  Proc fs(bin + "/tiller-failsafe", {"--config", cfg, "--lcm-url", kUrl});

  double heave = 0, volts = 15.5;
  bool wet = false;
  std::int64_t next = 0, arm_sent = -1;
  const std::int64_t t0 = realtime_us();
  auto feed = [&]() {  // 20 Hz: the stick, the battery, the probes
    const std::int64_t now = realtime_us();
    if (now < next) return;
    next = now + 50'000;
    manual_demand_t d{};
    d.utime = now;
    d.valid = true;
    d.demand[2] = heave;
    l.publish(channels::kManualDemand, &d);
    power_t p{};
    p.utime = now;
    p.voltage = volts;
    p.monitor = "test";
    l.publish(channels::kPower, &p);
    leak_t k{};
    k.utime = now;
    k.n_probes = 1;
    k.names = {"main_tube"};
    k.wet = {wet ? std::int8_t{1} : std::int8_t{0}};
    k.readable = {1};
    k.any_wet = wet;
    l.publish(channels::kLeak, &k);
    if (arm_sent < 0 && now - t0 > 1'500'000 && rx.arm.boot_nonce != 0) {
      arm_request_t a{};
      a.utime = now;
      a.arm = true;
      a.source = "test";
      a.boot_nonce = rx.arm.boot_nonce;  // tiller-esc's, from its arm state
      l.publish(channels::kArmRequest, &a);
      arm_sent = now;
    }
  };
  auto pump = [&](const std::function<bool()>& pred, double s) {
    const std::int64_t end = realtime_us() + static_cast<std::int64_t>(s * 1e6);
    while (realtime_us() < end && !pred()) {
      feed();
      l.handleTimeout(5);
    }
    return pred();
  };
  // Armed, gate ACTIVE with the stick centred; then the pilot pushes down.
  ASSERT_TRUE(
      pump([&] { return rx.arm.armed && rx.cmd.gate == thruster_command_t::GATE_ACTIVE; }, 8.0))
      << "not armed and active";
  heave = 0.5;
  ASSERT_TRUE(pump([&] { return rx.cmd.armed && rx.cmd.command[0] < -0.1; }, 2.0));
  // A wet probe: from the first wet leak_t to the first command at full up-thrust.
  std::int64_t wet_at = -1, full_at = -1;
  rx.on_cmd_cb = [&](const thruster_command_t& c, std::int64_t at) {
    if (wet_at > 0 && full_at < 0 && c.command[0] >= 0.9999 && c.command[3] >= 0.9999) full_at = at;
  };
  wet = true;
  next = 0;
  feed();
  wet_at = realtime_us();
  ASSERT_TRUE(pump([&] { return full_at > 0; }, 2.0)) << "no full up-thrust after the leak";
  EXPECT_EQ(rx.status.action, vehicle_status_t::ACTION_SURFACE);
  // Still full up-thrust 0.5 s later with the stick pushed down.
  pump([] { return false; }, 0.5);
  EXPECT_GE(rx.cmd.command[0], 0.9999);
  EXPECT_GE(rx.cmd.command[3], 0.9999);
  // The battery below critical: disarmed trigger_s + disarm_after_s later.
  volts = 12.9;
  const std::int64_t low_at = realtime_us();
  ASSERT_TRUE(pump([&] { return rx.disarmed_at > 0; }, 5.0)) << "not disarmed";
  std::printf(
      "leak -> full up-thrust: %.1f ms; battery below critical -> disarmed: %.2f s "
      "(trigger_s 0.5 + disarm_after_s 1.0)\n",
      (full_at - wet_at) / 1e3, (rx.disarmed_at - low_at) / 1e6);
  EXPECT_LT(full_at - wet_at, 300'000);  // a 10 Hz tick, plus the transport
  EXPECT_GT(rx.disarmed_at - low_at, 1'400'000);
  EXPECT_LT(rx.disarmed_at - low_at, 2'500'000);
  std::remove(cfg.c_str());
}

}  // namespace
}  // namespace tiller::e2e
