#include "guidance/path_follower_node.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <tiller/path_progress_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::guidance {

// Status lines as strings made once (set_health takes a std::string; no allocation per tick).
const std::string kIdle = "idle: no path";
const std::string kStale = "odometry stale: setpoint inactive";
const std::string kWaiting = "path waiting for odometry";
const std::string kComplete = "path complete";
const std::string kFollowing = "following";
const std::string kHoldingCourse =
    "GNSS outage (dead reckoning): holding the course and speed from before it";
const std::string kFollowingDr = "GNSS outage (dead reckoning): following the estimate";
const std::string kPaused = "paused: holding position (RESUME continues)";

PathFollowerNode::PathFollowerNode(const FollowerNodeParams& p)
    : Node("path-follower", from_hz(p.rate_hz)),
      p_(p),
      follower_(p.follower),
      odom_fresh_(from_seconds(p.odometry_timeout_s)) {
  subscribe(channels::kPath, &PathFollowerNode::on_path);
  subscribe(channels::kOdometry, &PathFollowerNode::on_odometry);
  subscribe(channels::kMode, &PathFollowerNode::on_mode);
  subscribe(channels::kMissionCommand, &PathFollowerNode::on_command);
  subscribe(channels::kPathSpeed, &PathFollowerNode::on_speed);
  subscribe(channels::kPidVelocity, &PathFollowerNode::on_pid);  // used with surge_integral_drag
  speeds_.path_id = -1;
  advertise<velocity_setpoint_t>(channels::kVelocitySetpoint);
  advertise<path_progress_t>(channels::kPathProgress);
  advertise<station_target_t>(channels::kStationTarget);
  nan_odometry_ = &counter("rejected.odometry.nan");
  invalid_path_ = &counter("rejected.path.invalid");
  paths_started_ = &counter("paths.started");
  pending_points_.reserve(64);
  dropped_ids_.fill(-2);  // no path id is -2 (ids are >= 0, -1 means none)
  set_health(heartbeat_t::STATE_OK, kIdle);
}

void PathFollowerNode::on_path(const path_t& m, TimeUs) {
  // Its contract (core/message_checks.hpp): 0..10000 waypoints, positions within 1e6 m,
  // headings (where given) in (-pi, pi].
  if (checks::check(m) != nullptr || static_cast<int>(m.waypoints.size()) != m.n_waypoints) {
    reject(*invalid_path_);
    return;
  }
  if (m.n_waypoints == 0) {  // cancel the path being followed
    if (follower_.has_path() || pending_) drop_path();
    path_id_ = m.path_id;
    return;
  }
  if (m.path_id == path_id_ && (follower_.has_path() || pending_)) return;  // repeat
  if (std::find(dropped_ids_.begin(), dropped_ids_.end(), m.path_id) != dropped_ids_.end()) {
    // A repeat of a cancelled or aborted path (tiller-mission repeats its path): stays dropped.
    if (!dropped_repeats_) dropped_repeats_ = &counter("paths.dropped_repeats");
    ++*dropped_repeats_;
    return;
  }
  path_id_ = m.path_id;
  paused_ = false;
  pending_points_.clear();
  for (const auto& w : m.waypoints) {
    Waypoint p;
    p.position = Vec2(w.position[0], w.position[1]);
    p.has_heading = w.has_heading;
    p.heading = w.has_heading ? w.heading : 0.0;
    pending_points_.push_back(p);
  }
  pending_ = true;
  if (odom_fresh_.ever()) start_pending_path();
}

void PathFollowerNode::drop_path() {
  dropped_ids_[next_dropped_slot_] = path_id_;
  next_dropped_slot_ = (next_dropped_slot_ + 1) % dropped_ids_.size();
  follower_.clear();
  pending_ = false;
  paused_ = false;
}

void PathFollowerNode::on_command(const mission_command_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {  // unknown command, id < 1
    if (!bad_command_) bad_command_ = &counter("rejected.mission_command.invalid");
    reject(*bad_command_);
    return;
  }
  for (const std::int64_t id : seen_commands_)
    if (id == m.command_id) return;  // an event already acted on
  seen_commands_[next_command_slot_] = m.command_id;
  next_command_slot_ = (next_command_slot_ + 1) % seen_commands_.size();
  switch (m.command) {
    case mission_command_t::PAUSE:
      if (follower_.has_path()) paused_ = true;
      break;
    case mission_command_t::RESUME:
      if (paused_) last_update_odom_time_ = -1;  // no integral step over the pause
      paused_ = false;
      break;
    case mission_command_t::ABORT:
    case mission_command_t::RELEASE:
      if (follower_.has_path() || pending_) drop_path();
      break;
    default:  // START: the mixer's gate acts on it
      break;
  }
}

void PathFollowerNode::start_pending_path() {
  pending_ = false;
  last_segment_ = 0;
  if (follower_.set_path(pending_points_, pos_, heading_, is_translation_)) ++*paths_started_;
  last_update_odom_time_ = -1;
}

void PathFollowerNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(odom_fresh_, m.utime, now, "odometry")) return;
  // The whole message against its contract (core/message_checks.hpp): non-finite values count
  // under rejected.odometry.nan, the rest (angles out of range, covariance size) under .range.
  if (const char* why = checks::check(m)) {
    if (std::string_view(why).ends_with(".nan")) {
      reject(*nan_odometry_);
    } else {
      // Made on first use, so the heartbeat of a run with good input is unchanged.
      if (!range_odometry_) range_odometry_ = &counter("rejected.odometry.range");
      reject(*range_odometry_);
    }
    return;
  }
  // Following needs the position and the heading (odometry_t.valid): without them the message
  // is not taken and the odometry goes stale (setpoint inactive).
  constexpr std::int32_t needs = int{odometry_t::VALID_POSITION} | int{odometry_t::VALID_ATTITUDE};
  if ((m.valid & needs) != needs) {
    if (!invalid_odometry_) invalid_odometry_ = &counter("odometry.invalid");
    ++*invalid_odometry_;
    return;
  }
  const bool dr = m.valid & odometry_t::DEAD_RECKONING;
  if (dr && !dead_reckoning_) {
    dr_since_ = now;
    held_ = out_;  // the last setpoint before the outage
    if (!outages_) outages_ = &counter("outages");
    ++*outages_;
  }
  if (!dr) dr_since_ = -1;
  dead_reckoning_ = dr;
  pos_ = Vec2(m.position[0], m.position[1]);
  heading_ = wrap_pi(m.orientation[2]);
  odom_time_ = m.utime;
  odom_fresh_.mark(now, m.utime, clock_offset());
  if (pending_) start_pending_path();
}

void PathFollowerNode::on_mode(const controller_mode_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {  // an unknown mode: its is_translation is not trusted
    if (!bad_mode_) bad_mode_ = &counter("rejected.mode.invalid");
    reject(*bad_mode_);
    return;
  }
  is_translation_ = m.is_translation;
  follower_.set_translation(is_translation_, heading_);
}

void PathFollowerNode::on_speed(const path_speed_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    if (!bad_speed_) bad_speed_ = &counter("rejected.path_speed.invalid");
    reject(*bad_speed_);
    return;
  }
  speeds_ = m;
}

void PathFollowerNode::on_pid(const pid_terms_t& m, TimeUs) {
  // Its contract first (every term finite): a bad one is counted whether or not it is used.
  if (checks::check(m) != nullptr) {
    if (!bad_pid_) bad_pid_ = &counter("rejected.pid_terms.nan");
    reject(*bad_pid_);
    return;
  }
  // A tuning message: taken only when it is the velocity PID's, finite and steady in surge.
  if (!(p_.follower.surge_integral_drag > 0) || m.controller != "velocity" ||
      m.integrator_frozen[0] || !std::isfinite(m.i[0]) || !std::isfinite(m.setpoint[0]) ||
      !std::isfinite(m.measured[0]) || std::abs(m.setpoint[0] - m.measured[0]) > kSteadySurgeError)
    return;
  if (!follower_.has_path() || paused_ || dead_reckoning_) return;
  follower_.observe_current_along(heading_, -m.i[0] / p_.follower.surge_integral_drag);
}

bool PathFollowerNode::holding_course(TimeUs now) const {
  return dead_reckoning_ && dr_since_ >= 0 && held_.active && !held_.complete &&
         now - dr_since_ < from_seconds(p_.outage_hold_course_s);
}

void PathFollowerNode::on_tick(TimeUs now) {
  const bool fresh = odom_fresh_.fresh(now);
  if (odom_fresh_.stale_events() > seen_stale_) {
    count_stale(odom_fresh_.stale_events() - seen_stale_);
    seen_stale_ = odom_fresh_.stale_events();
  }
  out_ = FollowerOutput{};
  if (fresh && follower_.has_path() && !paused_) {
    const double dt = last_update_odom_time_ < 0
                          ? 0.0
                          : std::max(0.0, to_seconds(odom_time_ - last_update_odom_time_));
    last_update_odom_time_ = odom_time_;
    // A mission's speed for the segment the follower is on (its last output's), else max_speed.
    double v = p_.follower.max_speed;
    const int seg = std::max(last_segment_, 0);
    if (speeds_.path_id == path_id_ && seg < speeds_.n_segments && speeds_.speed[seg] > 0)
      v = std::min(v, speeds_.speed[seg]);
    follower_.set_max_speed(v);
    if (holding_course(now)) {
      out_ = held_;  // the course and speed from before the outage; progress not advanced
    } else {
      out_ = follower_.update(pos_, heading_, dt);
      last_segment_ = out_.segment;
    }
  }

  velocity_setpoint_t sp{};
  sp.utime = now;
  sp.frame = velocity_setpoint_t::FRAME_NED;
  sp.active = out_.active;
  sp.velocity[0] = out_.velocity.x();
  sp.velocity[1] = out_.velocity.y();
  sp.heading_valid = out_.heading_valid;
  sp.target_heading = out_.target_heading;
  publish(channels::kVelocitySetpoint, sp);

  path_progress_t pr{};
  pr.utime = now;
  pr.path_id = follower_.has_path() ? path_id_ : -1;
  pr.segment = out_.active ? out_.segment : -1;
  pr.n_waypoints = static_cast<std::int32_t>(follower_.points().size());
  pr.cross_track_error = out_.cross_track;
  pr.along_track_error = out_.along_track_remaining;
  pr.distance_to_goal = out_.distance_to_goal;
  pr.complete = out_.complete;
  pr.skipped_waypoints = out_.skipped;
  publish(channels::kPathProgress, pr);

  station_target_t st{};
  st.utime = now;
  st.active = out_.active && out_.complete;
  if (st.active) {
    const auto& g = follower_.points().back();
    st.position[0] = g.position.x();
    st.position[1] = g.position.y();
    st.heading_valid = follower_.goal_heading_valid();
    st.heading = follower_.goal_heading();
  }
  publish(channels::kStationTarget, st);

  if (!fresh && follower_.has_path()) {
    set_health(heartbeat_t::STATE_DEGRADED, kStale);
  } else if (!follower_.has_path()) {
    set_health(heartbeat_t::STATE_OK, pending_ ? kWaiting : kIdle);
  } else if (dead_reckoning_ && !paused_) {
    set_health(heartbeat_t::STATE_DEGRADED, holding_course(now) ? kHoldingCourse : kFollowingDr);
  } else {
    set_health(heartbeat_t::STATE_OK, paused_ ? kPaused : out_.complete ? kComplete : kFollowing);
  }
}

}  // namespace tiller::guidance
