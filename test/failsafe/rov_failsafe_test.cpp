// The ROV's failsafes in closed loop, in lockstep: simulator + ESC (sim backend) + mixer for seed
// 001's 6-thruster ROV (two vertical thrusters) + tiller-failsafe's node, and a pilot (the test)
// who arms, centres the stick and then pushes down and keeps pushing. The test publishes the
// leak probes on the driver's channel (TILLER_LEAK).
//   * a leak at depth: the failsafe's wrench replaces the pilot's: full up-thrust (both vertical
//     thrusters at +1) however hard the pilot pushes down, to the surface; zero thrust there;
//   * the depth limit: the pilot pushing down never takes the ROV more than a few cm below it.
#include <gtest/gtest.h>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include "core/config.hpp"
#include "esc/esc_node.hpp"
#include "failsafe/failsafe_config.hpp"
#include "failsafe/failsafe_node.hpp"
#include "harness.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sim/sim_node.hpp"

namespace tiller::test {
namespace {

constexpr double kFull = 0.9999;  // a thruster command at full

struct RovRun {
  double max_depth = 0;           // m
  double depth_at_event = -1;     // m
  double event_at = -1;           // s: first action other than none / warn
  double full_up_at = -1;         // s: first command with both vertical thrusters at +1
  double surfaced_at = -1;        // s: depth < 0.3 m after the event
  double min_vertical_after = 2;  // smallest vertical command from full_up_at to surfaced_at
  double final_depth = 0;
  bool armed_at_end = false;
};

// The pilot's stick: `heave(t)` (normalised, + = down) from 2 s, centred before.
RovRun run_rov(const failsafe::FailsafeNodeParams& fs, double start_depth, double end_s,
               const std::function<double(double)>& heave,
               const std::function<void(LockstepExecutor&, TimeUs)>& feed) {
  const auto sroot = config::Value::load_file(source_path("config/sim/sim.yaml"));
  SimParams sp = load_sim_params(sroot);
  sp.vehicle_file = source_path("config/vehicles/seed001_rov6.yaml");
  sp.initial_eta.setZero();
  sp.initial_eta[2] = start_depth;
  sp.current.model = sim::CurrentParams::Model::kNone;
  SimNode sim(sp, load_sim_vehicle_file(sp.vehicle_file));
  EscNode esc(source_path("config/esc/seed001_sim.yaml"));
  MixerNode mixer(source_path("config/mixer/seed001_rov6.yaml"));
  failsafe::FailsafeNode failsafe(fs);
  LockstepExecutor ex(0);
  ex.add(sim);
  ex.add(esc);
  ex.add(mixer);
  ex.add(failsafe);
  arm_request_t a{};
  a.utime = 500'000;
  a.arm = true;
  a.source = "test";
  ex.inject(channels::kArmRequest, a, 500'000);
  for (TimeUs t = 0; t <= from_seconds(end_s); t += 50'000) {
    manual_demand_t d{};
    d.utime = t;
    d.valid = true;
    d.demand[2] = t < from_seconds(2) ? 0.0 : heave(to_seconds(t));
    ex.inject(channels::kManualDemand, d, t);
    feed(ex, t);
  }
  RovRun r;
  odometry_t o{};
  vehicle_status_t vs{};
  thruster_command_t cmd{};
  arm_state_t arm{};
  double depth = 0;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == channels::kGroundTruth && o.decode(d, 0, n) == n) {
      depth = o.position[2];
      r.max_depth = std::max(r.max_depth, depth);
      r.final_depth = depth;
      if (r.event_at >= 0 && r.surfaced_at < 0 && depth < 0.3) r.surfaced_at = ts;
    } else if (ch == channels::kVehicleStatus && vs.decode(d, 0, n) == n) {
      if (vs.action > vehicle_status_t::ACTION_WARN && r.event_at < 0) {
        r.event_at = ts;
        r.depth_at_event = depth;
      }
    } else if (ch == channels::kThrusterCommand && cmd.decode(d, 0, n) == n && cmd.armed) {
      // F and B are the vertical thrusters (+1 = full up; the T200 curve's inverse gives
      // 0.99995 at the allocator's limit).
      const double f = cmd.command[0], b = cmd.command[3];
      if (r.event_at >= 0 && r.full_up_at < 0 && f >= kFull && b >= kFull) r.full_up_at = ts;
      if (r.full_up_at >= 0 && r.surfaced_at < 0)
        r.min_vertical_after = std::min({r.min_vertical_after, f, b});
    } else if (ch == channels::kArmState && arm.decode(d, 0, n) == n) {
      r.armed_at_end = arm.armed;
    }
  });
  ex.run_until(from_seconds(end_s));
  std::printf(
      "ROV: max depth %.3f m, event at %.2f s at %.2f m, full up-thrust at %.2f s, surfaced at "
      "%.2f s, min vertical command meanwhile %.2f, final depth %.2f m, armed %d\n",
      r.max_depth, r.event_at, r.depth_at_event, r.full_up_at, r.surfaced_at, r.min_vertical_after,
      r.final_depth, r.armed_at_end);
  return r;
}

leak_t leak(TimeUs t, bool wet) {
  leak_t m{};
  m.utime = t;
  m.n_probes = 1;
  m.names = {"main_tube"};
  m.wet = {wet ? std::int8_t{1} : std::int8_t{0}};
  m.readable = {1};
  m.any_wet = wet;
  return m;
}

TEST(RovFailsafe, ALeakSurfacesWithFullUpThrustWhateverThePilotDoes) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/seed001_rov6.yaml"));
  fs.monitor.battery.enabled = false;
  fs.monitor.depth.enabled = false;
  // From 10 m, the pilot pushes down at 0.8 from 2 s to the end; a probe is wet from 8 s.
  const auto r = run_rov(
      fs, 10.0, 60, [](double) { return 0.8; },
      [](LockstepExecutor& ex, TimeUs t) {
        if (t % 100'000 == 0) ex.inject(channels::kLeak, leak(t, t >= from_seconds(8)), t);
      });
  EXPECT_GT(r.depth_at_event, 10.5);            // the pilot took it down first
  EXPECT_NEAR(r.event_at, 8.0, 0.11);           // leak.trigger_s 0: at the next tick
  EXPECT_LE(r.full_up_at - r.event_at, 0.001);  // the same instant: the mixer acts on it at once
  EXPECT_GE(r.min_vertical_after, kFull);       // full up-thrust until the surface
  EXPECT_GT(r.surfaced_at, 0);
  EXPECT_LT(r.final_depth, 0.35);
  EXPECT_TRUE(r.armed_at_end);  // no disarm_after_s in this config
}

TEST(RovFailsafe, ALeakWithDisarmConfiguredDisarms) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/seed001_rov6.yaml"));
  fs.monitor.battery.enabled = false;
  fs.monitor.depth.enabled = false;
  fs.monitor.leak.action = failsafe::Action::kDisarm;
  const auto r = run_rov(
      fs, 10.0, 12, [](double) { return 0.8; },
      [](LockstepExecutor& ex, TimeUs t) {
        if (t % 100'000 == 0) ex.inject(channels::kLeak, leak(t, t >= from_seconds(8)), t);
      });
  EXPECT_NEAR(r.event_at, 8.0, 0.11);
  EXPECT_FALSE(r.armed_at_end);
}

TEST(RovFailsafe, TheDepthLimitHoldsAgainstAPilotPushingDown) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/seed001_rov6.yaml"));
  fs.monitor.battery.enabled = false;
  fs.monitor.leak.enabled = false;
  fs.monitor.depth.limit_m = 5.0;
  // From 2 m the pilot pushes down at 0.8; every 5 s he centres the stick for 0.5 s and pushes
  // again (after a failsafe rise the gate waits for a centred stick).
  const auto r = run_rov(
      fs, 2.0, 60, [](double s) { return std::fmod(s, 5.0) < 0.5 ? 0.0 : 0.8; },
      [](LockstepExecutor&, TimeUs) {});
  EXPECT_GT(r.event_at, 0);
  EXPECT_GT(r.max_depth, 4.9);
  EXPECT_LT(r.max_depth, 5.15);
}

}  // namespace
}  // namespace tiller::test
