#include "control/station_keep_node.hpp"

#include "control/arbiter.hpp"

#include <tiller/pid_terms_t.hpp>

#include <cmath>
#include <string_view>

#include "control/integrator_gate.hpp"
#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::control {

// Status lines as strings made once (set_health takes a std::string; no allocation per tick).
const std::string kHolding = "odometry stale: holding the last wrench";
const std::string kNeutral = "odometry stale: neutral";
const std::string kRefused =
    "position hold refused: odometry has no valid position and velocity (no position source, or "
    "dead reckoning past its limit): neutral";
const std::string kRefusedHolding =
    "position hold refused: odometry has no valid position and velocity: holding the last wrench";
const std::string kRefusedNeutral =
    "position hold refused: odometry has no valid position and velocity (the estimator says so): "
    "neutral, armed; resumes when it is valid";
// What station keeping needs of an odometry message (odometry_t.valid).
constexpr std::int32_t kNeeds = int{odometry_t::VALID_POSITION} | int{odometry_t::VALID_VELOCITY} |
                                int{odometry_t::VALID_ATTITUDE};
const std::string kNoTarget = "idle: no target";
const std::string kKeeping = "station keeping";
const std::string kStandby = "standing by (not the active source)";
const std::string kHoldingHere = "holding position where the vehicle was (no target)";

namespace {
constexpr int kAxis[3] = {0, 1, 5};
}

StationKeepNode::StationKeepNode(const StationKeepNodeParams& p)
    : Node("station-keep", from_hz(p.common.rate_hz)),
      p_(p),
      pid_(p.pid),
      odom_fresh_(from_seconds(p.common.odometry_timeout_s)),
      target_fresh_(from_seconds(p.common.input_timeout_s)),
      arb_fresh_(from_seconds(p.common.input_timeout_s)),
      alloc_fresh_(from_seconds(p.common.allocation_timeout_s)),
      velocity_fresh_(from_seconds(p.common.input_timeout_s)),
      command_fresh_(from_seconds(p.common.allocation_timeout_s)),
      blend_(p.common.blend_s) {
  subscribe(channels::kWrenchVelocity, &StationKeepNode::on_velocity_wrench);
  subscribe(channels::kOdometry, &StationKeepNode::on_odometry);
  subscribe(channels::kStationTarget, &StationKeepNode::on_target);
  subscribe(channels::kArbitration, &StationKeepNode::on_arbitration);
  subscribe(channels::kAllocationStatus, &StationKeepNode::on_allocation);
  subscribe(channels::kThrusterCommand, &StationKeepNode::on_thruster_command);
  advertise<wrench_t>(channels::kWrenchStation);
  advertise<pid_terms_t>(channels::kPidStation);
  nan_odometry_ = &counter("rejected.odometry.nan");
  bad_target_ = &counter("rejected.target.invalid");
  bad_velocity_wrench_ = &counter("rejected.wrench_velocity.nan");
  // Strings sized once, so a hand-over allocates nothing (autonomy_alloc_test): the copy of the
  // arbitration (its reason) and the heartbeat's status.
  arb_.reason.reserve(Arbiter::kMaxReasonLength);
  set_health(heartbeat_t::STATE_OK, std::string(Arbiter::kMaxReasonLength, ' '));
  set_health(heartbeat_t::STATE_OK, "starting");
}

std::int64_t& StationKeepNode::first_use(std::int64_t*& c, const char* name) {
  // Made on the first rejection, so the heartbeat of a run with good input is unchanged.
  if (c == nullptr) c = &counter(name);
  return *c;
}

void StationKeepNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(odom_fresh_, m.utime, now, "odometry")) return;
  // The whole message against its contract (core/message_checks.hpp): non-finite values count
  // under rejected.odometry.nan, the rest (angles out of range, covariance size) under .range.
  if (const char* why = checks::check(m)) {
    reject(std::string_view(why).ends_with(".nan")
               ? *nan_odometry_
               : first_use(range_odometry_, "rejected.odometry.range"));
    return;
  }
  // A well-formed estimate without the parts a hold needs: not taken, so the odometry goes
  // stale (docs/safety.md: hold the last wrench for hold_s or neutral), and said so.
  odom_invalid_ = (m.valid & kNeeds) != kNeeds;
  estimate_.on_message(odom_invalid_, now);
  if (odom_invalid_) {
    ++first_use(invalid_odometry_, "odometry.invalid");
    return;
  }
  odom_ = m;
  odom_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::on_target(const station_target_t& m, TimeUs now) {
  if (!on_time(target_fresh_, m.utime, now, "station_target")) return;
  // An active target must meet its contract (core/message_checks.hpp: heading, when valid, in
  // (-pi, pi]) and lie within 1e6 m; an inactive one only cancels, its fields are not used.
  if (m.active && (!all_in_range(m.position, -1e6, 1e6) || checks::check(m) != nullptr)) {
    reject(*bad_target_);
    return;
  }
  if (!m.active) hold_heading_valid_ = false;
  target_ = m;
  target_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::on_arbitration(const arbitration_t& m, TimeUs now) {
  if (!on_time(arb_fresh_, m.utime, now, "arbitration")) return;
  if (checks::check(m) != nullptr) {  // unknown mode or source
    reject(first_use(bad_arbitration_, "rejected.arbitration.invalid"));
    return;
  }
  arb_ = m;
  arb_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::on_allocation(const allocation_status_t& m, TimeUs now) {
  if (!on_time(alloc_fresh_, m.utime, now, "allocation")) return;
  if (checks::check(m) != nullptr) {  // unknown source, NaN, scale outside [0, 1], ...
    reject(first_use(bad_allocation_, "rejected.allocation.invalid"));
    return;
  }
  alloc_ = m;
  alloc_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::on_velocity_wrench(const wrench_t& m, TimeUs now) {
  if (!on_time(velocity_fresh_, m.utime, now, "wrench_velocity")) return;
  // Its contract (core/message_checks.hpp): a known source, each component within +-1e5 (it is
  // re-published as our own wrench while standing by). Dropped: the last good one (or none)
  // stays in force. Non-finite under .nan, the rest under .range.
  if (checks::check(m) != nullptr) {
    reject(all_finite(m.tau) ? first_use(range_velocity_wrench_, "rejected.wrench_velocity.range")
                             : *bad_velocity_wrench_);
    return;
  }
  velocity_wrench_ = m;
  velocity_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::on_thruster_command(const thruster_command_t& m, TimeUs now) {
  if (!on_time(command_fresh_, m.utime, now, "thruster_command")) return;
  if (checks::check(m) != nullptr) {  // unknown source or gate, commands out of [-1, 1]
    reject(first_use(bad_command_, "rejected.thruster_command.invalid"));
    return;
  }
  command_gate_ = m.gate;
  command_source_ = m.source;
  command_fresh_.mark(now, m.utime, clock_offset());
}

void StationKeepNode::publish_wrench(TimeUs now, bool valid, double x, double y, double n) {
  wrench_t w{};
  w.utime = now;
  w.source = wrench_t::SOURCE_STATION_KEEP;
  w.valid = valid;
  w.tau[0] = x;
  w.tau[1] = y;
  w.tau[5] = n;
  publish(channels::kWrenchStation, w);
  last_wrench_ = w;
}

void StationKeepNode::on_tick(TimeUs now) {
  active_ = arb_fresh_.fresh(now) && arb_.active_source == wrench_t::SOURCE_STATION_KEEP;
  const bool entering = active_ && !was_active_;
  if (!active_) {
    pid_.reset();
    blend_.stop();
  } else if (!was_active_ && velocity_fresh_.fresh(now) && velocity_wrench_.valid) {
    blend_.start(now, {velocity_wrench_.tau[0], velocity_wrench_.tau[1], velocity_wrench_.tau[5]});
  }
  was_active_ = active_;

  const bool odom_ok = odom_fresh_.fresh(now);
  if (odom_fresh_.stale_events() > seen_stale_) {
    count_stale(odom_fresh_.stale_events() - seen_stale_);
    seen_stale_ = odom_fresh_.stale_events();
  }
  if (!odom_ok) {
    const bool hold =
        p_.common.on_stale == StaleAction::kHold && odom_fresh_.ever() &&
        now - odom_fresh_.last() <= odom_fresh_.limit() + from_seconds(p_.common.hold_s);
    invalid_neutral_ =
        !hold && estimate_.neutral(now, odom_fresh_.limit(),
                                   from_seconds(p_.common.invalid_neutral_s), odom_fresh_.ever());
    if (hold) {
      publish_wrench(now, last_wrench_.valid, last_wrench_.tau[0], last_wrench_.tau[1],
                     last_wrench_.tau[5]);
      set_health(heartbeat_t::STATE_DEGRADED, odom_invalid_ ? kRefusedHolding : kHolding);
    } else if (invalid_neutral_) {
      // The estimator is alive and says its estimate is not good enough (estimate_watch.hpp): a
      // deliberate neutral, so the vehicle stays armed and carries on when it is valid again.
      publish_wrench(now, true, 0, 0, 0);
      set_health(heartbeat_t::STATE_DEGRADED, kRefusedNeutral);
    } else {
      // Invalid: no wrench to give (nothing to hold on). The mixer counts it as input lost:
      // neutral at once, and a disarm request after safety.disarm_after_s.
      publish_wrench(now, false, 0, 0, 0);
      set_health(heartbeat_t::STATE_DEGRADED, odom_invalid_ ? kRefused : kNeutral);
    }
    last_odom_utime_ = -1;
    return;
  }

  if (invalid_neutral_) {
    // Valid again after a deliberate neutral: ramp from that zero wrench over blend_s.
    invalid_neutral_ = false;
    if (active_) blend_.start(now, {0, 0, 0});
  }
  const bool have_target = target_fresh_.fresh(now) && target_.active;
  const double heading = wrap_pi(odom_.orientation[2]);
  if (have_target && !target_.heading_valid && (!hold_heading_valid_ || !active_)) {
    // Keep the heading the vehicle has when it arrives (re-captured until we take control).
    hold_heading_ = heading;
    hold_heading_valid_ = true;
  }
  // Integrate only while the mixer applies this wrench (gate ACTIVE): reset while disarmed or
  // waiting for a start, so a start begins from zero integral; frozen otherwise.
  const IntegratorRule rule = integrator_rule(command_fresh_.fresh(now), command_gate_,
                                              command_source_, wrench_t::SOURCE_STATION_KEEP);
  if (rule == IntegratorRule::kReset) pid_.reset();
  // In control without a target: hold where the vehicle is (captured on taking control, and
  // again while nothing has been started).
  const bool hold_here = active_ && !have_target;
  if (!hold_here) {
    hold_here_valid_ = false;
  } else if (!hold_here_valid_ || rule == IntegratorRule::kReset) {
    hold_n_ = odom_.position[0];
    hold_e_ = odom_.position[1];
    hold_psi_ = heading;
    hold_here_valid_ = true;
  }
  StationPidInput in;
  in.target_n = hold_here ? hold_n_ : target_.position[0];
  in.target_e = hold_here ? hold_e_ : target_.position[1];
  in.target_heading = hold_here               ? hold_psi_
                      : target_.heading_valid ? target_.heading
                                              : hold_heading_;
  in.n = odom_.position[0];
  in.e = odom_.position[1];
  in.heading = heading;
  in.u = odom_.velocity[0];
  in.v = odom_.velocity[1];
  in.r = odom_.velocity[5];
  // Integrate only while in control, and not on the entry tick (the integrator is exactly zero
  // when station keeping takes over).
  in.dt = (last_odom_utime_ < 0 || !active_ || entering)
              ? 0.0
              : to_seconds(odom_.utime - last_odom_utime_);
  last_odom_utime_ = odom_.utime;
  const bool alloc_ok = alloc_fresh_.fresh(now) && alloc_.source == wrench_t::SOURCE_STATION_KEEP;
  for (int k = 0; k < 3; ++k) {
    in.freeze[static_cast<std::size_t>(k)] =
        rule != IntegratorRule::kIntegrate ||
        (alloc_ok && (alloc_.axis_reduced[kAxis[k]] || alloc_.axis_unactuated[kAxis[k]]));
  }
  const bool steer = have_target || hold_here;
  terms_ = steer ? pid_.step(in) : PidTerms{};
  if (steer && active_) terms_.out = blend_.apply(now, terms_.out);
  if (!active_ && velocity_fresh_.fresh(now) && velocity_wrench_.valid) {
    // Standing by: track the velocity PID's wrench, so a mixer that switches to us before our
    // next tick sees no step (bumpless hand-over); the terms still show our own law.
    publish_wrench(now, true, velocity_wrench_.tau[0], velocity_wrench_.tau[1],
                   velocity_wrench_.tau[5]);
  } else {
    publish_wrench(now, steer, terms_.out[0], terms_.out[1], terms_.out[2]);
  }

  pid_terms_t t{};
  t.utime = now;
  t.controller = "station";
  for (int k = 0; k < 3; ++k) {
    t.setpoint[k] = terms_.setpoint[k];
    t.measured[k] = terms_.measured[k];
    t.p[k] = terms_.p[k];
    t.i[k] = terms_.i[k];
    t.d[k] = terms_.d[k];
    t.feed_forward[k] = terms_.ff[k];
    t.output[k] = terms_.out[k];
    t.integrator_frozen[k] = terms_.frozen[k];
  }
  publish(channels::kPidStation, t);
  set_health(heartbeat_t::STATE_OK, hold_here      ? kHoldingHere
                                    : !have_target ? kNoTarget
                                    : active_      ? kKeeping
                                                   : kStandby);
}

}  // namespace tiller::control
