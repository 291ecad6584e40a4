// Mode changes to and from manual, in lockstep on the full Otter stack (simulator + ESC + mixer +
// path follower + velocity PID + station keeping), 0.3 m/s current from 30 deg:
//   manual open loop (the pilot's stick straight to the mixer) -> waypointing -> manual.
// Taking over from the stick, the velocity PID starts with its integrators at zero and blends
// from what the mixer achieved with the stick to its own wrench over blend_s: no thrust step.
// Back to manual open loop, the stick is authoritative at once (a deliberate instant switch:
// the pilot takes over because the autonomy is not doing what they want, so the autonomy's
// wrench must not linger for a blend time).
// And manual closed loop (the pilot's velocity through the velocity PID) -> waypointing ->
// manual closed loop, with a path loaded throughout: the source is VELOCITY_PID all along, so
// only the mode changes; each switch resets the PID's integrators and blends from the wrench it
// last published, both ways (the pilot's closed-loop command goes through the same PID).
#include <gtest/gtest.h>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/wrench_t.hpp>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/angles.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "harness.hpp"
#include "mission/mission.hpp"
#include "plants.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {
namespace {

struct Change {
  double t = 0;             // s: when the mode was sent
  std::int8_t mode = 0;     // controller_mode_t
  double switched_at = -1;  // s: when the arbitration followed
  double max_step = 0;      // N: largest step of the achieved [X Y] within 2 s after
  bool i_zero_on_entry = false;
  bool stick_at_once = false;  // the stick is allocated at the instant of the switch
  double unblended_jump = 0;   // N: |own wrench - wrench in force| at entry (no blend)
  double i_before = 0;         // N: |integral terms| on the PID tick before the switch
};

struct ModeRun {
  std::vector<Change> changes;
  bool i_zero_while_standing_by = true;
  double max_step_steady = 0;  // N: largest step outside the 2 s windows (for scale)
};

// Runs `changes` (mode sent each second from its time on) until end_s, with the pilot's stick
// (open loop) and closed-loop velocity command (u = 0.3 m/s, no yaw rate) both sent throughout.
ModeRun run_modes(const std::string& vehicle_name, std::vector<Change> changes, double end_s) {
  const PlantSpec* spec = nullptr;
  for (const auto& p : plants()) {
    if (p.name == vehicle_name) spec = &p;
  }
  EXPECT_NE(spec, nullptr);
  mission::Mission m;
  m.start = mission::MissionPoint{0, 0, true, 0};
  m.waypoints = {{0, 0, false, 0}, {200, 0, false, 0}, {200, 100, false, 0}};
  auto plant = spec->make(m, 0.3, deg_to_rad(30));
  const auto groot = config::Value::load_file(source_path(spec->guidance_file));
  guidance::PathFollowerNode follower(guidance::load_follower_node_params(groot));
  const auto croot = source_path(spec->control_file);
  control::VelocityPidNode vpid(
      control::load_velocity_pid_node_params(config::Value::load_file(croot)));
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  LockstepExecutor ex(0);
  for (auto& p : plant) ex.add(*p);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);

  ModeRun r;
  r.changes = std::move(changes);
  manual_demand_t stick{};
  stick.demand[0] = 0.5;  // half ahead, a little starboard yaw
  stick.demand[5] = 0.1;
  stick.valid = true;
  manual_velocity_cmd_t pilot{};
  pilot.velocity[0] = 0.3;  // m/s ahead, holding the yaw rate at zero
  pilot.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
  pilot.valid = true;

  std::int8_t source = -1;
  std::int8_t arb_mode = -1;
  double last_i = 0;          // |integral terms| of the last pid_terms
  int current = -1;           // index of the change in force
  bool expect_entry = false;  // next velocity pid_terms is the entry tick
  bool expect_stick = false;  // next allocation status is the first after the switch
  double last_x = NAN, last_y = NAN;
  arbitration_t arb{};
  allocation_status_t st{};
  pid_terms_t terms{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    const double ts = to_seconds(t);
    if (ch == channels::kArbitration && arb.decode(d, 0, n) == n) {
      // A change of source, or of mode with the source unchanged (closed loop <-> waypointing).
      if (arb.active_source != source || arb.mode != arb_mode) {
        for (int k = static_cast<int>(r.changes.size()) - 1; k >= 0; --k) {
          if (ts >= r.changes[static_cast<std::size_t>(k)].t) {
            current = k;
            break;
          }
        }
        auto& c = r.changes[static_cast<std::size_t>(current)];
        if (c.switched_at < 0) c.switched_at = ts;
        expect_entry = arb.active_source == wrench_t::SOURCE_VELOCITY_PID;
        expect_stick = arb.active_source == wrench_t::SOURCE_MANUAL_DEMAND;
        source = arb.active_source;
        arb_mode = arb.mode;
      }
    } else if (ch == channels::kPidVelocity && terms.decode(d, 0, n) == n) {
      const bool zero = terms.i[0] == 0 && terms.i[1] == 0 && terms.i[2] == 0;
      if (expect_entry) {
        auto& c = r.changes[static_cast<std::size_t>(current)];
        c.i_zero_on_entry = zero;
        c.i_before = last_i;
        // The PID's own wrench at entry against what was in force: the step without a blend.
        c.unblended_jump = std::hypot(terms.feed_forward[0] + terms.p[0] + terms.i[0] - last_x,
                                      terms.feed_forward[1] + terms.p[1] + terms.i[1] - last_y);
        expect_entry = false;
      } else if (source != wrench_t::SOURCE_VELOCITY_PID && !zero) {
        r.i_zero_while_standing_by = false;
      }
      last_i = std::abs(terms.i[0]) + std::abs(terms.i[1]) + std::abs(terms.i[2]);
    } else if (ch == channels::kAllocationStatus && st.decode(d, 0, n) == n) {
      if (expect_stick && current >= 0) {
        // The mixer's own tick at this instant ran before the arbitration arrived; the stick
        // must be in force by the end of the instant of the switch.
        auto& c = r.changes[static_cast<std::size_t>(current)];
        if (ts > c.switched_at) {
          expect_stick = false;
        } else {
          bool same = st.source == wrench_t::SOURCE_MANUAL_DEMAND;
          for (int k = 0; k < 6; ++k) same = same && st.demanded[k] == stick.demand[k];
          c.stick_at_once = c.stick_at_once || same;
        }
      }
      const double x = st.achieved[0], y = st.achieved[1];
      if (!std::isnan(last_x)) {
        const double step = std::hypot(x - last_x, y - last_y);
        bool in_window = false;
        for (auto& c : r.changes) {
          if (c.switched_at >= 0 && ts >= c.switched_at && ts <= c.switched_at + 2.0) {
            c.max_step = std::max(c.max_step, step);
            in_window = true;
          }
        }
        if (!in_window && ts > 2.0) r.max_step_steady = std::max(r.max_step_steady, step);
      }
      last_x = x;
      last_y = y;
    }
  });

  const path_t path = mission::to_path(m, 7, 0);
  arm_request_t arm{};
  arm.arm = true;
  arm.source = "mode-test";
  for (TimeUs t = 0; t <= from_seconds(end_s); t += 50'000) {
    if (t % kUsPerSecond == 0) {
      arm.utime = t;
      ex.inject(channels::kArmRequest, arm, t);
      path_t p = path;
      p.utime = t;
      ex.inject(channels::kPath, p, t);
      controller_mode_t mode{};
      mode.utime = t;
      mode.source = "mode-test";
      for (const auto& c : r.changes) {
        if (to_seconds(t) >= c.t) mode.mode = c.mode;
      }
      ex.inject(channels::kMode, mode, t);
    }
    // The pilot's stick is held, except while the pilot centres it: before arming, and for
    // 0.3 s after each switch back to a manual mode (the safety gate, docs/safety.md, holds
    // thrust neutral until then). A switch to waypointing comes with the operator's go (as the
    // teleop's autonomous button sends).
    bool centring = t < 500'000;
    for (std::size_t k = 1; k < r.changes.size(); ++k) {
      const TimeUs ct = from_seconds(r.changes[k].t);
      if (r.changes[k].mode != controller_mode_t::WAYPOINTING && t >= ct && t < ct + 300'000)
        centring = true;
      if (r.changes[k].mode == controller_mode_t::WAYPOINTING && t == ct) {
        mission_command_t go{};
        go.utime = t;
        go.command_id = static_cast<std::int64_t>(k);
        go.command = mission_command_t::RESUME;
        go.source = "mode-test";
        ex.inject(channels::kMissionCommand, go, t);
      }
    }
    manual_demand_t held = stick;
    if (centring)
      for (double& v : held.demand) v = 0;
    held.utime = t;
    ex.inject(channels::kManualDemand, held, t);
    pilot.utime = t;
    ex.inject(channels::kManualVelocity, pilot, t);
  }
  ex.run_until(from_seconds(end_s));
  return r;
}

// The bound on the step is 20 N for the Otter (240 N ahead): 8 % of its thrust; the same 8 %
// of seed 004's X drive (650 N ahead) is 55 N. The step without the blend is printed: the
// blend spreads it over blend_s (1 s, 20 ticks).
TEST(ModeChange, ManualToWaypointingBlendsFromTheStickAndBackIsInstant) {
  const std::pair<const char*, double> boats[] = {{"otter", 20.0}, {"seed004_usv_x", 55.0}};
  for (const auto& [v, bound] : boats) {
    SCOPED_TRACE(v);
    const ModeRun r = run_modes(v,
                                {{0, controller_mode_t::MANUAL_OPEN_LOOP},
                                 {10, controller_mode_t::WAYPOINTING},
                                 {30, controller_mode_t::MANUAL_OPEN_LOOP}},
                                40);
    EXPECT_TRUE(r.i_zero_while_standing_by);
    const Change& to_auto = r.changes[1];
    const Change& to_manual = r.changes[2];
    ASSERT_GE(to_auto.switched_at, 10.0);
    ASSERT_GE(to_manual.switched_at, 30.0);
    // Taking over from the stick: integrators at zero, no thrust step.
    EXPECT_TRUE(to_auto.i_zero_on_entry);
    EXPECT_LT(to_auto.max_step, bound);  // N per mixer output, within 2 s
    // Back to the stick: a held stick is NOT in force at the switch; the safety gate holds
    // neutral until the pilot has centred it (docs/safety.md).
    EXPECT_FALSE(to_manual.stick_at_once);
    std::printf(
        "%s: manual -> waypointing: largest step %.1f N in 2 s (%.1f N without the blend); "
        "waypointing -> manual: %.1f N (neutral until centred); elsewhere up to %.1f N\n",
        v, to_auto.max_step, to_auto.unblended_jump, to_manual.max_step, r.max_step_steady);
  }
}

// Manual closed loop -> waypointing -> manual closed loop, mid-path: the source stays
// VELOCITY_PID, only the setpoint changes (the pilot's 0.3 m/s or the follower's). Each switch
// resets the integrators (zero on the switch tick, after 10 s / 20 s of integrating) and blends
// from the last published wrench over blend_s, both ways; same bounds as above (8 % of thrust).
TEST(ModeChange, ClosedLoopToWaypointingAndBackBlendsWithIntegratorsReset) {
  const std::pair<const char*, double> boats[] = {{"otter", 20.0}, {"seed004_usv_x", 55.0}};
  for (const auto& [v, bound] : boats) {
    SCOPED_TRACE(v);
    const ModeRun r = run_modes(v,
                                {{0, controller_mode_t::MANUAL_CLOSED_LOOP},
                                 {10, controller_mode_t::WAYPOINTING},
                                 {30, controller_mode_t::MANUAL_CLOSED_LOOP}},
                                40);
    const Change& to_auto = r.changes[1];
    const Change& to_manual = r.changes[2];
    ASSERT_GE(to_auto.switched_at, 10.0);
    ASSERT_LT(to_auto.switched_at, 11.0);  // the path was loaded: waypointing follows it at once
    ASSERT_GE(to_manual.switched_at, 30.0);
    ASSERT_LT(to_manual.switched_at, 31.0);
    for (const Change* c : {&to_auto, &to_manual}) {
      // The integrator had built up under the previous command, and is zero on the switch tick.
      EXPECT_GT(c->i_before, 0.0);
      EXPECT_TRUE(c->i_zero_on_entry);
    }
    // N per mixer output, within 2 s. Back to the pilot the safety gate holds neutral until
    // the stick is centred (0.3 s here), so that hand-over is a hold, not a blend.
    EXPECT_LT(to_auto.max_step, bound);
    std::printf(
        "%s closed loop: manual -> waypointing: largest step %.1f N in 2 s (%.1f N without the "
        "blend); waypointing -> manual: %.1f N (%.1f N without); elsewhere up to %.1f N\n",
        v, to_auto.max_step, to_auto.unblended_jump, to_manual.max_step, to_manual.unblended_jump,
        r.max_step_steady);
  }
}

}  // namespace
}  // namespace tiller::test
