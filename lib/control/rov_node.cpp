#include "control/rov_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>

#include <tiller/heartbeat_t.hpp>

#include "control/integrator_gate.hpp"
#include "core/angles.hpp"
#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::control {

namespace {

std::array<double, 6> axis_max(const Allocator& a, int sign) {
  std::array<double, 6> m{};
  for (int i = 0; i < 6; ++i) m[static_cast<std::size_t>(i)] = a.axis_max(i, sign);
  return m;
}

constexpr std::size_t kReasonRoom = 256;
// What the assisted modes need of an odometry message (odometry_t.valid): every one the attitude
// and rates; the modes that use the depth (uses_depth) also the depth; position hold also the
// horizontal position and velocity.
constexpr std::int32_t kNeeds = odometry_t::VALID_ATTITUDE;
constexpr std::int32_t kNeedsForPosition = kNeeds | int{odometry_t::VALID_DEPTH} |
                                           int{odometry_t::VALID_POSITION} |
                                           int{odometry_t::VALID_VELOCITY};

}  // namespace

RovControlNode::RovControlNode(const RovControlParams& p)
    : RovControlNode(p, load_vehicle_file(p.vehicle_file)) {}

RovControlNode::RovControlNode(const RovControlParams& p, const Vehicle& vehicle)
    : Node("rov-control", from_hz(p.rate_hz)),
      p_(p),
      alloc_(std::make_unique<Allocator>(vehicle)),
      vehicle_name_(vehicle.name),
      axes_(p.axes, axis_max(*alloc_, 1), axis_max(*alloc_, -1)),
      mode_(controller_mode_t::MANUAL_OPEN_LOOP),
      odom_fresh_(from_seconds(p.odometry_timeout_s)),
      depth_fresh_(from_seconds(p.odometry_timeout_s)),
      manual_fresh_(from_seconds(p.input_timeout_s)),
      alloc_fresh_(from_seconds(p.allocation_timeout_s)),
      cmd_fresh_(from_seconds(p.allocation_timeout_s)) {
  for (std::size_t a = 0; a < 6; ++a) actuated_[a] = !alloc_->unactuated()[a];
  subscribe(channels::kMode, &RovControlNode::on_mode);
  subscribe(channels::kManualDemand, &RovControlNode::on_manual);
  subscribe(channels::kArmState, &RovControlNode::on_arm_state);
  rejected_station_ = &counter("rejected.manual_demand.station");
  subscribe(channels::kOdometry, &RovControlNode::on_odometry);
  subscribe(channels::kAllocationStatus, &RovControlNode::on_allocation);
  subscribe(channels::kThrusterCommand, &RovControlNode::on_thruster_command);
  for (Freshness* f : {&setpoint_fresh_, &station_fresh_, &progress_fresh_})
    f->set_limit(from_seconds(p.input_timeout_s));
  subscribe(channels::kVelocitySetpoint, &RovControlNode::on_setpoint);
  subscribe(channels::kStationTarget, &RovControlNode::on_station_target);
  subscribe(channels::kPath, &RovControlNode::on_path);
  subscribe(channels::kPathProgress, &RovControlNode::on_progress);
  bad_setpoint_ = &counter("rejected.velocity_setpoint.invalid");
  bad_station_ = &counter("rejected.station_target.invalid");
  bad_path_ = &counter("rejected.path.invalid");
  bad_progress_ = &counter("rejected.path_progress.invalid");
  advertise<wrench_t>(channels::kWrenchRov);
  advertise<arbitration_t>(channels::kArbitration);
  advertise<controller_mode_t>(channels::kMode);  // position hold's fallback (fall_back)
  mode_msg_.source = "rov-control";
  position_lost_ = &counter("position_hold.lost");
  nan_odometry_ = &counter("rejected.odometry.nan");
  range_odometry_ = &counter("rejected.odometry.range");
  invalid_odometry_ = &counter("odometry.invalid");
  bad_manual_ = &counter("rejected.manual_demand.invalid");
  bad_mode_ = &counter("rejected.mode.invalid");
  unavailable_ = &counter("mode.refused");
  bad_allocation_ = &counter("rejected.allocation.invalid");
  bad_command_ = &counter("rejected.thruster_command.invalid");
  switches_ = &counter("mode.switches");
  // Strings sized once: a mode change or a refusal allocates nothing.
  reason_.reserve(kReasonRoom);
  refusal_.reserve(kReasonRoom);
  status_.reserve(kReasonRoom);
  arb_.reason.reserve(kReasonRoom);
  set_health(heartbeat_t::STATE_OK, std::string(kReasonRoom, ' '));
  wrench_.source = wrench_t::SOURCE_ROV_CONTROL;
  set_reason("manual: the stick straight to the mixer");
  if (p_.default_mode != controller_mode_t::MANUAL_OPEN_LOOP) {
    ModePlan plan;
    // No odometry yet: a default mode that uses the depth waits for it (neutral until then).
    if (!plan_rov_mode(p_.default_mode, actuated_, false, true, vehicle_name_, plan, refusal_))
      throw config::Error("rov_control.default_mode: " + refusal_);
    switch_to(p_.default_mode, plan, 0);
    blending_ = false;
  }
}

void RovControlNode::set_reason(const char* text) {
  reason_.assign(text);
  status_.assign(reason_);
  set_health(heartbeat_t::STATE_OK, status_);
}

bool RovControlNode::position_valid(TimeUs now) {
  if (!odom_fresh_.fresh(now)) return false;
  if ((odom_.valid & kNeedsForPosition) != kNeedsForPosition) return false;
  if (odom_.n_pose_cov != 36) return !p_.require_position_covariance;
  const double lim = p_.max_position_std_m * p_.max_position_std_m;
  return odom_.pose_covariance[0] <= lim && odom_.pose_covariance[7] <= lim;
}

void RovControlNode::on_mode(const controller_mode_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kEventMaxAgeUs, "mode")) return;  // a stopped process's queue
  if (checks::check(m) != nullptr) {
    reject(*bad_mode_);
    return;
  }
  if (m.mode == requested_) return;  // a repeat (the teleop repeats its mode every second)
  requested_ = m.mode;
  if (m.mode != controller_mode_t::WAYPOINTING) refused_waypointing_ = false;
  ModePlan plan;
  if (m.mode == controller_mode_t::MANUAL_OPEN_LOOP ||
      plan_rov_mode(m.mode, actuated_, position_valid(now), depth_fresh_.fresh(now), vehicle_name_,
                    plan, refusal_)) {
    switch_to(m.mode, plan, now);
    return;
  }
  // A mission's waypointing is asked again with its repeats (tiller-mission's TILLER_MODE every
  // second), so it starts once the position is valid (the mixer's gate still waits for START);
  // a pilot's mode is not: a refused position hold never engages by itself later.
  const bool retry = m.mode == controller_mode_t::WAYPOINTING;
  if (retry) requested_ = -1;
  if (retry && refused_waypointing_) return;  // counted and said once
  refused_waypointing_ = retry;
  ++*unavailable_;  // a well-formed request the vehicle cannot fly: counted, not a bad message
  char buf[kReasonRoom];
  std::snprintf(buf, sizeof buf, "%s; still in %s", refusal_.c_str(), rov_mode_words(mode_));
  set_reason(buf);
}

void RovControlNode::switch_to(std::int8_t mode, const ModePlan& plan, TimeUs now) {
  if (mode == mode_ && !leaving_) return;
  ++*switches_;
  from_ = last_out_;
  blend_start_ = now;
  char buf[kReasonRoom];
  if (mode == controller_mode_t::MANUAL_OPEN_LOOP) {
    // Blend into what the mixer's open-loop allocation gives, then hand the stick to it.
    leaving_ = mode_ != controller_mode_t::MANUAL_OPEN_LOOP && p_.blend_s > 0;
    blending_ = false;
    mode_ = mode;
    if (!leaving_) axes_.set_roles({}, false);
    set_reason("manual: the stick straight to the mixer");
    return;
  }
  leaving_ = false;
  blending_ = p_.blend_s > 0;
  if (mode == controller_mode_t::WAYPOINTING && mode_ != mode) {
    depth_ref_ = state_.depth;  // the references start where the vehicle is
    heading_ref_ = state_.yaw;
  }
  plan_ = plan;
  mode_ = mode;
  axes_.set_roles(plan.roles, plan.level);
  std::snprintf(buf, sizeof buf, "%s on %s", rov_mode_words(mode), vehicle_name_.c_str());
  set_reason(buf);
}

void RovControlNode::fall_back(TimeUs now) {
  // The position is lost (odometry fresh, but without a valid position or velocity: the DVL's
  // bottom lock lost, its driver stopped): the configured mode, else heading hold, else manual.
  ++*position_lost_;
  const std::int8_t from = mode_;
  const bool depth = depth_fresh_.fresh(now);
  ModePlan plan;
  std::int8_t to = p_.position_loss_mode;
  if (to != controller_mode_t::MANUAL_OPEN_LOOP &&
      !plan_rov_mode(to, actuated_, false, depth, vehicle_name_, plan, refusal_)) {
    to = controller_mode_t::HEADING_HOLD;
    if (!plan_rov_mode(to, actuated_, false, depth, vehicle_name_, plan, refusal_))
      to = controller_mode_t::MANUAL_OPEN_LOOP;
  }
  switch_to(to, plan, now);
  // Not resumed silently: the pilot's station (the teleop, the cockpit) takes this as the mode
  // in force, so its repeats carry it, and position hold comes back only when asked for again.
  requested_ = to;
  mode_msg_.utime = now;
  mode_msg_.mode = to;
  mode_msg_.is_translation = false;
  Node::publish(channels::kMode, mode_msg_);
  char buf[kReasonRoom];
  std::snprintf(buf, sizeof buf,
                "position lost (no valid position in the odometry: DVL bottom lock or driver): "
                "%s -> %s; select %s again to resume",
                rov_mode_words(from), rov_mode_words(to), rov_mode_words(from));
  set_reason(buf);
  set_health(heartbeat_t::STATE_DEGRADED, status_);
}

void RovControlNode::on_arm_state(const arm_state_t& m, TimeUs now) {
  // Only the station in control matters here; freshness and arming are the mixer's and the ESC's.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "arm_state")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.arm_state.invalid"));  // made on first use
    return;
  }
  stations_.on_arm_state(m);
}

void RovControlNode::on_manual(const manual_demand_t& m, TimeUs now) {
  if (!on_time(manual_fresh_, m.utime, now, "manual_demand")) return;
  if (!stations_.allows(m.station)) {  // another station's stick: not ours to follow
    reject(*rejected_station_);
    return;
  }
  if (checks::check(m) != nullptr) {
    manual_fresh_.reset();
    reject(*bad_manual_);
    return;
  }
  if (!m.valid) {
    manual_fresh_.reset();  // the teleop says: no stick (absent, not centred yet)
    return;
  }
  std::copy(m.demand, m.demand + 6, stick_.begin());
  manual_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(odom_fresh_, m.utime, now, "odometry")) return;
  if (const char* why = checks::check(m)) {
    reject(std::string_view(why).ends_with(".nan") ? *nan_odometry_ : *range_odometry_);
    return;
  }
  // Without a valid attitude (and rates) the message is not taken: the odometry goes stale, so
  // the assisted modes give an invalid wrench (neutral through the mixer's gate). Without a
  // valid depth it is taken but its depth is not: the depth goes stale, which only the modes
  // that use it see (counted when the mode in force is one of them).
  const bool depth_ok = (m.valid & odometry_t::VALID_DEPTH) != 0;
  const bool assisted = mode_ != controller_mode_t::MANUAL_OPEN_LOOP;
  if ((m.valid & kNeeds) != kNeeds || (!depth_ok && assisted && uses_depth(plan_))) {
    ++*invalid_odometry_;
    if ((m.valid & kNeeds) != kNeeds) return;
  }
  odom_ = m;
  state_.north = m.position[0];
  state_.east = m.position[1];
  if (depth_ok) {
    state_.depth = m.position[2];
    depth_fresh_.mark(now, m.utime, clock_offset());
  }
  state_.roll = m.orientation[0];
  state_.pitch = m.orientation[1];
  state_.yaw = m.orientation[2];
  std::copy(m.velocity, m.velocity + 6, state_.nu.begin());
  odom_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_allocation(const allocation_status_t& m, TimeUs now) {
  if (!on_time(alloc_fresh_, m.utime, now, "allocation_status")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_allocation_);
    return;
  }
  alloc_source_ = m.source;
  for (std::size_t a = 0; a < 6; ++a) {
    achieved_[a] = m.achieved[a];
    reduced_[a] = m.axis_reduced[a];
  }
  alloc_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_thruster_command(const thruster_command_t& m, TimeUs now) {
  if (!on_time(cmd_fresh_, m.utime, now, "thruster_command")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_command_);
    return;
  }
  gate_ = m.gate;
  cmd_source_ = m.source;
  cmd_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_setpoint(const velocity_setpoint_t& m, TimeUs now) {
  if (!on_time(setpoint_fresh_, m.utime, now, "velocity_setpoint")) return;
  if (checks::check(m) != nullptr) {
    setpoint_fresh_.reset();
    reject(*bad_setpoint_);
    return;
  }
  setpoint_ = m;
  setpoint_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_station_target(const station_target_t& m, TimeUs now) {
  if (!on_time(station_fresh_, m.utime, now, "station_target")) return;
  // As tiller-station-keep takes it: the contract, and an active target within 1e6 m.
  if ((m.active && !all_in_range(m.position, -1e6, 1e6)) || checks::check(m) != nullptr) {
    station_fresh_.reset();
    reject(*bad_station_);
    return;
  }
  station_ = m;
  station_fresh_.mark(now, m.utime, clock_offset());
}

void RovControlNode::on_path(const path_t& m, TimeUs) {
  if (checks::check(m) != nullptr) {
    reject(*bad_path_);
    return;
  }
  path_ = m;  // a new path: the one copy it needs (not per tick)
}

void RovControlNode::on_progress(const path_progress_t& m, TimeUs now) {
  if (!on_time(progress_fresh_, m.utime, now, "path_progress")) return;
  if (checks::check(m) != nullptr) {
    progress_fresh_.reset();
    reject(*bad_progress_);
    return;
  }
  progress_ = m;
  progress_fresh_.mark(now, m.utime, clock_offset());
}

double RovControlNode::path_depth() const {
  const auto& w = path_.waypoints;
  if (w.empty() || progress_.path_id != path_.path_id) return depth_ref_;  // no path: as it is
  const auto n = static_cast<std::int32_t>(w.size());
  const std::int32_t s = progress_.segment;
  if (progress_.complete || s < 0 || s + 1 >= n)
    return w[static_cast<std::size_t>(n - 1)].position[2];
  const auto& a = w[static_cast<std::size_t>(s)].position;
  const auto& b = w[static_cast<std::size_t>(s + 1)].position;
  const double dn = b[0] - a[0], de = b[1] - a[1], l2 = dn * dn + de * de;
  const double t =
      l2 > 0 ? std::clamp(((state_.north - a[0]) * dn + (state_.east - a[1]) * de) / l2, 0.0, 1.0)
             : 1.0;
  return a[2] + t * (b[2] - a[2]);
}

void RovControlNode::guide_roles(TimeUs now, std::array<AxisRole, 6>& roles,
                                 std::array<double, 6>& stick) {
  stick = {};  // the pilot's stick is not in waypointing's path
  const bool was_at_station = at_station_;
  at_station_ = station_fresh_.fresh(now) && station_.active;
  if (at_station_ && !was_at_station) {
    station_ref_[0] = state_.north;
    station_ref_[1] = state_.east;
  }
  const bool follow = !at_station_ && setpoint_fresh_.fresh(now) && setpoint_.active;
  if (!follow) {
    // The station target, or no guidance (none yet, or lost): X and Y hold (where the vehicle
    // stops, without a target).
    roles[0] = roles[1] = AxisRole::kHold;
    return;
  }
  double u = setpoint_.velocity[0], v = setpoint_.velocity[1];
  if (setpoint_.frame == velocity_setpoint_t::FRAME_NED) {
    const double c = std::cos(state_.yaw), s = std::sin(state_.yaw);
    u = c * setpoint_.velocity[0] + s * setpoint_.velocity[1];
    v = -s * setpoint_.velocity[0] + c * setpoint_.velocity[1];
  }
  stick[0] = std::clamp(u / p_.axes[0].max_rate, -1.0, 1.0);
  stick[1] = std::clamp(v / p_.axes[1].max_rate, -1.0, 1.0);
}

void RovControlNode::guide_targets(TimeUs now, double dt) {
  if (dt <= 0) return;
  // Depth: toward the path's depth at half the heave max_rate.
  const double dz = std::clamp(path_depth() - depth_ref_, -0.5 * p_.axes[2].max_rate * dt,
                               0.5 * p_.axes[2].max_rate * dt);
  depth_ref_ += dz;
  axes_.guide(2, depth_ref_, dz / dt);
  // Heading: toward the follower's (or the station's) heading at half the yaw max_rate.
  const bool hv = at_station_
                      ? station_.heading_valid
                      : setpoint_fresh_.fresh(now) && setpoint_.active && setpoint_.heading_valid;
  double dh = 0;
  if (hv) {
    const double goal = at_station_ ? station_.heading : setpoint_.target_heading;
    dh = std::clamp(angle_diff(goal, heading_ref_), -0.5 * p_.axes[5].max_rate * dt,
                    0.5 * p_.axes[5].max_rate * dt);
    heading_ref_ = wrap_pi(heading_ref_ + dh);
  }
  axes_.guide(5, heading_ref_, dh / dt);
  if (at_station_) {
    // Toward the target along the straight line, at most half the surge max_rate.
    const double dn = station_.position[0] - station_ref_[0];
    const double de = station_.position[1] - station_ref_[1];
    const double d = std::hypot(dn, de), step = 0.5 * p_.axes[0].max_rate * dt;
    const double k = d > step ? step / d : 1.0;
    station_ref_[0] += k * dn;
    station_ref_[1] += k * de;
    axes_.guide(0, station_ref_[0], k * dn / dt);
    axes_.guide(1, station_ref_[1], k * de / dt);
  }
}

void RovControlNode::publish(TimeUs now, std::int8_t source, bool valid) {
  wrench_.utime = now;
  wrench_.valid = valid;
  for (std::size_t a = 0; a < 6; ++a) wrench_.tau[a] = valid ? last_out_[a] : 0.0;
  arb_.utime = now;
  arb_.mode = mode_;
  arb_.active_source = source;
  arb_.is_translation = false;
  arb_.reason.assign(reason_);
  // Order: a valid wrench before the arbitration that may name it, an invalid one after the
  // arbitration that names another source, so that the mixer never sees the source in control
  // without its input (which its gate would take for an input loss and want the stick centred).
  if (valid) Node::publish(channels::kWrenchRov, wrench_);
  Node::publish(channels::kArbitration, arb_);
  if (!valid) Node::publish(channels::kWrenchRov, wrench_);
}

void RovControlNode::on_tick(TimeUs now) {
  const bool odom_ok = odom_fresh_.fresh(now);
  const bool pilot_ok = manual_fresh_.fresh(now);
  const bool cmd_ok = cmd_fresh_.fresh(now);
  const bool alloc_ok = alloc_fresh_.fresh(now);
  const std::int64_t stale = odom_fresh_.stale_events() + manual_fresh_.stale_events() +
                             cmd_fresh_.stale_events() + alloc_fresh_.stale_events();
  if (stale > stale_seen_) {
    count_stale(stale - stale_seen_);
    stale_seen_ = stale;
  }
  const bool thrust_on = cmd_ok && gate_ == thruster_command_t::GATE_ACTIVE;

  if (mode_ == controller_mode_t::MANUAL_OPEN_LOOP && !leaving_) {
    // What the mixer achieves with the stick: where the next switch blends from.
    if (thrust_on && alloc_ok && alloc_source_ == wrench_t::SOURCE_MANUAL_DEMAND)
      last_out_ = achieved_;
    else if (!thrust_on)
      last_out_ = {};
    publish(now, wrench_t::SOURCE_MANUAL_DEMAND, false);
    return;
  }
  if ((mode_ == controller_mode_t::POSITION_HOLD || mode_ == controller_mode_t::WAYPOINTING) &&
      !leaving_ && odom_ok && !position_valid(now))
    fall_back(now);
  const bool guided = mode_ == controller_mode_t::WAYPOINTING && !leaving_;
  if (!odom_ok || !(pilot_ok || guided) || (uses_depth(plan_) && !depth_fresh_.fresh(now))) {
    // No state (or no depth, in a mode that uses it) or no pilot: an invalid wrench, so neutral
    // through the mixer's gate (input lost, then its disarm).
    last_out_ = {};
    publish(now, wrench_t::SOURCE_ROV_CONTROL, false);
    return;
  }

  // The mode's roles this tick: surface leaves heave alone near the top; position hold without
  // a position gives the horizontal axes to the pilot.
  std::array<AxisRole, 6> roles = plan_.roles;
  std::array<double, 6> stick = stick_;
  if (plan_.surface) {
    if (state_.depth <= p_.surface_depth_m) {
      roles[2] = AxisRole::kOff;
    } else {
      stick[2] = std::clamp(-p_.surface_speed_m_s / p_.axes[2].max_rate, -1.0, 1.0);
    }
  }
  if (guided) guide_roles(now, roles, stick);
  if (!leaving_) axes_.set_roles(roles, plan_.level);

  const IntegratorRule rule =
      integrator_rule(cmd_ok, gate_, cmd_source_, wrench_t::SOURCE_ROV_CONTROL);
  std::array<bool, 6> reduced{};
  if (alloc_ok && alloc_source_ == wrench_t::SOURCE_ROV_CONTROL) reduced = reduced_;
  const double dt = static_cast<double>(tick_period()) * 1e-6;
  if (guided) {
    if (rule == IntegratorRule::kReset) {  // not started: the references follow the vehicle
      depth_ref_ = state_.depth;
      heading_ref_ = state_.yaw;
    }
    guide_targets(now, dt);
  }
  std::array<double, 6> own = axes_.step(state_, stick, dt, rule, reduced);

  if (!thrust_on) {
    // Nothing reaches the thrusters (disarmed, waiting for the centred stick): no blend to
    // finish, the next start begins from the mode's own output.
    blending_ = false;
    if (leaving_) {
      leaving_ = false;
      axes_.set_roles({}, false);
      last_out_ = {};
      publish(now, wrench_t::SOURCE_MANUAL_DEMAND, false);
      return;
    }
  }
  const double a =
      p_.blend_s > 0
          ? std::clamp(static_cast<double>(now - blend_start_) / (p_.blend_s * 1e6), 0.0, 1.0)
          : 1.0;
  if (leaving_) {
    Wrench j;
    for (int k = 0; k < 6; ++k) j(k) = stick_[static_cast<std::size_t>(k)];
    if (!alloc_->allocate_manual(j, manual_result_)) alloc_->neutral(manual_result_);
    for (std::size_t k = 0; k < 6; ++k)
      last_out_[k] = a * manual_result_.achieved(static_cast<int>(k)) + (1 - a) * from_[k];
    publish(now, wrench_t::SOURCE_ROV_CONTROL, true);
    if (a >= 1.0) {
      leaving_ = false;
      axes_.set_roles({}, false);
    }
    return;
  }
  if (blending_) {
    for (std::size_t k = 0; k < 6; ++k) own[k] = a * own[k] + (1 - a) * from_[k];
    if (a >= 1.0) blending_ = false;
  }
  last_out_ = own;
  publish(now, wrench_t::SOURCE_ROV_CONTROL, true);
}

}  // namespace tiller::control
