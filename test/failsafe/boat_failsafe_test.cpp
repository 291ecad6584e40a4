// The boat's failsafes in closed loop, in lockstep on the full Otter stack (simulator + ESC +
// mixer + path follower + velocity PID with the arbiter + station keeping + tiller-mission's node
// + tiller-failsafe's node), a 150 m leg north at 1.5 m/s in a 0.3 m/s current from 30 deg. The
// test publishes the sensor readings on the drivers' channels (TILLER_POWER, TILLER_GNSS):
//   * battery critical at speed: the boat holds where it is (station keeping, within its
//     stopping distance), armed; disarm_after_s later the failsafe disarms it;
//   * GNSS lost: holds within the stopping distance; fixes back: the leg completes;
//   * a geofence across the leg: the boat stops before the edge and never crosses it.
#include <gtest/gtest.h>

#include <tiller/arbitration_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/angles.hpp"
#include "failsafe/failsafe_config.hpp"
#include "failsafe/failsafe_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "plants.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {
namespace {

struct BoatRun {
  double event_at = -1;       // s: the failsafe's first action other than none / warn
  double speed_at_event = 0;  // m/s over ground
  double max_after = 0;       // m from where the boat was at the event, while the action held
                              // (until a disarm: then the boat drifts with the current)
  double final_distance = 0;  // m, at the end (or when the action ended, or at the disarm)
  double disarmed_at = -1;    // s
  double max_north = -1e9;    // m
  bool completed = false;
  double completed_at = -1;
  std::int8_t source_in_hold = -1;  // the arbiter's source 1 s after the event
  std::string reason;               // the failsafe's reason at the event
};

// Runs the leg for end_s with the failsafe config `fs` and the sensor feed `feed(t)` (called
// every 100 ms of simulated time before the run; it injects what it wants).
BoatRun run_boat(const failsafe::FailsafeNodeParams& fs, double end_s,
                 const std::function<void(LockstepExecutor&, TimeUs)>& feed) {
  const PlantSpec& spec = plants()[0];  // the Otter, full stack
  mission::Mission m;
  m.name = "failsafe";
  m.start = mission::MissionPoint{0, 0, true, 0};
  m.waypoints = {{0, 0, false, 0}, {150, 0, false, 0}};
  auto plant = spec.make(m, 0.3, deg_to_rad(30));
  const auto groot = config::Value::load_file(source_path(spec.guidance_file));
  guidance::PathFollowerNode follower(guidance::load_follower_node_params(groot));
  const auto croot = source_path(spec.control_file);
  control::VelocityPidNode vpid(
      control::load_velocity_pid_node_params(config::Value::load_file(croot)));
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  mission::MissionNode mission(m, 5, kUsPerSecond);
  failsafe::FailsafeNode failsafe(fs);
  LockstepExecutor ex(0);
  for (auto& p : plant) ex.add(*p);
  ex.add(mission);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);
  ex.add(failsafe);
  for (TimeUs t = 0; t <= from_seconds(end_s); t += 100'000) feed(ex, t);

  BoatRun r;
  bool acting = false, armed_seen = false;
  double on = 0, oe = 0;
  odometry_t o{};
  vehicle_status_t vs{};
  arbitration_t arb{};
  arm_state_t arm{};
  path_progress_t pr{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == spec.pose_channel && o.decode(d, 0, n) == n) {
      r.max_north = std::max(r.max_north, o.position[0]);
      if (acting && r.disarmed_at < 0) {
        if (r.speed_at_event < 0) {
          on = o.position[0];
          oe = o.position[1];
          r.speed_at_event = std::hypot(o.velocity[0], o.velocity[1]);
        }
        r.final_distance = std::hypot(o.position[0] - on, o.position[1] - oe);
        r.max_after = std::max(r.max_after, r.final_distance);
      }
    } else if (ch == channels::kVehicleStatus && vs.decode(d, 0, n) == n) {
      const bool act =
          vs.action != vehicle_status_t::ACTION_NONE && vs.action != vehicle_status_t::ACTION_WARN;
      if (act && r.event_at < 0) {
        r.event_at = ts;
        r.speed_at_event = -1;
        r.reason = vs.reason;
      }
      acting = act;
    } else if (ch == channels::kArbitration && arb.decode(d, 0, n) == n) {
      if (r.event_at >= 0 && r.source_in_hold < 0 && ts >= r.event_at + 1.0)
        r.source_in_hold = arb.active_source;
    } else if (ch == channels::kArmState && arm.decode(d, 0, n) == n) {
      armed_seen = armed_seen || arm.armed;
      if (armed_seen && !arm.armed && r.disarmed_at < 0) r.disarmed_at = ts;
    } else if (ch == channels::kPathProgress && pr.decode(d, 0, n) == n) {
      if (pr.complete && !r.completed) {
        r.completed = true;
        r.completed_at = ts;
      }
    }
  });
  ex.run_until(from_seconds(end_s));
  std::printf(
      "failsafe at %.2f s (%s): speed %.2f m/s, max distance after %.2f m, at the end %.2f m, "
      "source 1 s after %d, disarmed at %.2f s, max north %.2f m, completed %d at %.1f s\n",
      r.event_at, r.reason.c_str(), r.speed_at_event, r.max_after, r.final_distance,
      r.source_in_hold, r.disarmed_at, r.max_north, r.completed, r.completed_at);
  return r;
}

power_t power(TimeUs t, double v) {
  power_t p{};
  p.utime = t;
  p.voltage = v;
  p.current = 20;
  p.power = v * 20;
  p.monitor = "test";
  return p;
}

TEST(BoatFailsafe, BatteryCriticalHoldsThenDisarms) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/otter.yaml"));
  fs.monitor.gnss.enabled = false;
  fs.monitor.battery.disarm_after = from_seconds(20);
  // 22.5 V, then 19.5 V (below critical 19.8 V) from 40 s: critical at 42 s (trigger_s 2).
  const auto r = run_boat(fs, 75, [](LockstepExecutor& ex, TimeUs t) {
    ex.inject(channels::kPower, power(t, t < from_seconds(40) ? 22.5 : 19.5), t);
  });
  EXPECT_NEAR(r.event_at, 42.0, 0.11);
  EXPECT_GT(r.speed_at_event, 1.3);
  EXPECT_EQ(r.source_in_hold, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_LT(r.max_after, 2.5);            // the stopping distance (hold_test: 1.72 m)
  EXPECT_NEAR(r.disarmed_at, 62.0, 0.2);  // disarm_after_s 20 s after critical
  EXPECT_FALSE(r.completed);
}

gnss_fix_t fix(TimeUs t) {
  gnss_fix_t f{};
  f.utime = t;
  f.fix_type = gnss_fix_t::FIX_3D;
  f.satellites = 10;
  f.latitude = 59.4;
  f.longitude = 10.5;
  f.device = "test";
  return f;
}

TEST(BoatFailsafe, GnssLostHoldsAndTheLegCompletesWhenFixesReturn) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/otter.yaml"));
  fs.monitor.battery.enabled = false;
  // Fixes at 5 Hz until 30 s, none until 70 s, then again: lost at 35 s (lost_after_s 5), back
  // at 72 s (recover_s 2).
  const auto r = run_boat(fs, 150, [](LockstepExecutor& ex, TimeUs t) {
    if ((t / 100'000) % 2 == 0 && (t <= from_seconds(30) || t >= from_seconds(70)))
      ex.inject(channels::kGnss, fix(t), t);
  });
  EXPECT_NEAR(r.event_at, 35.0, 0.11);
  EXPECT_EQ(r.source_in_hold, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_LT(r.max_after, 2.5);
  EXPECT_TRUE(r.completed);
  EXPECT_LT(r.disarmed_at, 0);
}

TEST(BoatFailsafe, GeofenceStopsTheBoatBeforeTheEdgeAndItNeverCrosses) {
  auto fs = failsafe::load_failsafe_file(source_path("config/failsafe/otter.yaml"));
  fs.monitor.battery.enabled = false;
  fs.monitor.gnss.enabled = false;
  fs.monitor.geofence.enabled = true;
  fs.monitor.geofence.polygon = {{-20, -20}, {-20, 20}, {60, 20}, {60, -20}};  // edge at n = 60
  const auto r = run_boat(fs, 100, [](LockstepExecutor&, TimeUs) {});
  // At 1.5 m/s the point 2 s ahead reaches 1 m from the edge at n = 56.
  EXPECT_GT(r.event_at, 0);
  EXPECT_EQ(r.source_in_hold, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_LT(r.max_north, 60.0);
  EXPECT_GT(r.max_north, 55.0);
  EXPECT_FALSE(r.completed);
}

}  // namespace
}  // namespace tiller::test
