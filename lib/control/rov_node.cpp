#include "control/rov_node.hpp"

#include <algorithm>
#include <cstdio>
#include <string_view>

#include <tiller/heartbeat_t.hpp>

#include "control/integrator_gate.hpp"
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
  ModePlan plan;
  if (m.mode == controller_mode_t::MANUAL_OPEN_LOOP ||
      plan_rov_mode(m.mode, actuated_, position_valid(now), depth_fresh_.fresh(now), vehicle_name_,
                    plan, refusal_)) {
    switch_to(m.mode, plan, now);
    return;
  }
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
                "position hold -> %s; select position hold again to resume",
                rov_mode_words(to));
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
  if (mode_ == controller_mode_t::POSITION_HOLD && !leaving_ && odom_ok && !position_valid(now))
    fall_back(now);
  if (!odom_ok || !pilot_ok || (uses_depth(plan_) && !depth_fresh_.fresh(now))) {
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
  if (!leaving_) axes_.set_roles(roles, plan_.level);

  const IntegratorRule rule =
      integrator_rule(cmd_ok, gate_, cmd_source_, wrench_t::SOURCE_ROV_CONTROL);
  std::array<bool, 6> reduced{};
  if (alloc_ok && alloc_source_ == wrench_t::SOURCE_ROV_CONTROL) reduced = reduced_;
  const double dt = static_cast<double>(tick_period()) * 1e-6;
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
