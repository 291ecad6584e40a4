#include "harness.hpp"

#include <tiller/arbitration_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include <chrono>
#include <cmath>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/angles.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "mission/mission_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "simple_plant.hpp"

namespace tiller::test {

std::string source_path(const std::string& rel) {
  return rel.empty() || rel[0] == '/' ? rel : std::string(TILLER_SOURCE_DIR) + "/" + rel;
}

RunResult run_mission(const RunConfig& c) {
  RunResult r;
  r.mission = mission::load_mission_file(source_path(c.mission_file));
  const auto& m = r.mission;
  const double hold = c.hold_s >= 0 ? c.hold_s : m.station_keep_s;
  const double from = deg_to_rad(c.current_from_deg);

  std::vector<std::unique_ptr<Node>> plant;
  if (c.make_plant) {
    plant = c.make_plant(m, c.current_speed, from);
  } else {
    const auto s = m.start.value_or(mission::MissionPoint{});
    plant.push_back(
        std::make_unique<SimplePlant>(c.current_speed, from, s.north, s.east, s.heading));
  }
  const auto groot = config::Value::load_file(source_path(c.guidance_file));
  auto fparams = guidance::load_follower_node_params(groot);
  groot.check_all_used();
  if (c.tweak_follower) c.tweak_follower(fparams);
  guidance::PathFollowerNode follower(fparams);
  const auto croot = source_path(c.control_file);
  control::VelocityPidNode vpid(
      control::load_velocity_pid_node_params(config::Value::load_file(croot)));
  control::StationKeepNode skeep(
      control::load_station_keep_node_params(config::Value::load_file(croot)));
  mission::MissionNode mnode(m, 1, kUsPerSecond);

  LockstepExecutor ex(0);
  for (auto& p : plant) ex.add(*p);
  ex.add(mnode);
  ex.add(follower);
  ex.add(vpid);
  ex.add(skeep);

  std::int8_t source = -1;
  wrench_t wv{}, ws{};
  double last_x = 0, last_y = 0;
  TimeUs switched_until = -1;
  odometry_t o{};
  o.valid = odometry_t::VALID_ALL;
  path_progress_t pr{};
  arbitration_t arb{};
  velocity_setpoint_t sp{};
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    if (ch == c.pose_channel) {
      if (o.decode(d, 0, n) == n) {
        r.poses.push_back({to_seconds(t), o.position[0], o.position[1], o.orientation[2]});
      }
    } else if (ch == channels::kVelocitySetpoint) {
      if (sp.decode(d, 0, n) == n && sp.active && sp.frame == velocity_setpoint_t::FRAME_NED) {
        r.max_setpoint_speed =
            std::max(r.max_setpoint_speed, std::hypot(sp.velocity[0], sp.velocity[1]));
      }
    } else if (ch == channels::kPathProgress) {
      if (pr.decode(d, 0, n) == n && pr.complete && !r.completed) {
        r.completed = true;
        r.completed_at = to_seconds(t);
      }
      r.skipped = pr.skipped_waypoints;
    } else if (ch == channels::kArbitration) {
      if (arb.decode(d, 0, n) == n && arb.active_source != source) {
        if (source >= 0) ++r.switches;
        // A hand-over between the two controllers (not a start from neutral or manual).
        const bool handover = (source == wrench_t::SOURCE_VELOCITY_PID &&
                               arb.active_source == wrench_t::SOURCE_STATION_KEEP) ||
                              (source == wrench_t::SOURCE_STATION_KEEP &&
                               arb.active_source == wrench_t::SOURCE_VELOCITY_PID);
        if (handover) switched_until = t + 2 * kUsPerSecond;
        source = arb.active_source;
      }
    } else if (ch == channels::kWrenchVelocity || ch == channels::kWrenchStation) {
      wrench_t& w = ch == channels::kWrenchVelocity ? wv : ws;
      w.decode(d, 0, n);
      const std::int8_t src = ch == channels::kWrenchVelocity ? wrench_t::SOURCE_VELOCITY_PID
                                                              : wrench_t::SOURCE_STATION_KEEP;
      if (src != source) return;
      const double x = w.valid ? w.tau[0] : 0, y = w.valid ? w.tau[1] : 0;
      if (t <= switched_until) {
        r.max_switch_jump = std::max(r.max_switch_jump, std::hypot(x - last_x, y - last_y));
      }
      last_x = x;
      last_y = y;
      r.max_force = std::max(r.max_force, std::abs(x));
    }
  });

  const auto w0 = std::chrono::steady_clock::now();
  const TimeUs limit = from_seconds(c.time_limit_s >= 0 ? c.time_limit_s : m.time_limit_s);
  TimeUs t = 0;
  while (t < limit) {
    t += kUsPerSecond;
    ex.run_until(t);
    if (r.completed && to_seconds(t) >= r.completed_at + hold) break;
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  r.sim_s = to_seconds(t);

  std::vector<scores::Goal> path;
  for (const auto& w : m.waypoints) path.push_back({w.north, w.east, w.has_heading, w.heading});
  // The path starts where the follower starts it: for a one-point mission, at the start pose.
  path = scores::path_as_followed(path, r.poses, 0.0);
  r.path = scores::score_path(r.poses, path, 0.0,
                              r.completed ? std::optional<double>(r.completed_at) : std::nullopt);
  r.corners = scores::corner_scores(r.poses, path, 0.0, 60, r.completed ? r.completed_at : 1e300);
  if (r.completed) {
    r.held_s = r.sim_s - r.completed_at;
    r.station_vrx = scores::vrx_station_keeping(r.poses, path.back(), r.completed_at, r.sim_s);
    r.station_max_distance =
        scores::max_distance(r.poses, path.back(), r.completed_at + 10, r.sim_s);
  }
  return r;
}

}  // namespace tiller::test
