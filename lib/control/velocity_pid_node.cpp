#include "control/velocity_pid_node.hpp"

#include <tiller/arbitration_t.hpp>
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
const std::string kInvalid = "odometry has no valid velocity and attitude: neutral";
const std::string kInvalidHolding =
    "odometry has no valid velocity and attitude: holding the last wrench";
const std::string kInvalidNeutral =
    "odometry has no valid velocity and attitude (the estimator says so): neutral, armed; "
    "resumes when it is valid";
// What the velocity PID needs of an odometry message (odometry_t.valid): u v r and heading.
constexpr std::int32_t kNeeds = int{odometry_t::VALID_VELOCITY} | int{odometry_t::VALID_ATTITUDE};

namespace {
constexpr int kAxis[3] = {0, 1, 5};  // [X Y N] in tau / allocation_status_t arrays
}

VelocityPidNode::VelocityPidNode(const VelocityPidNodeParams& p)
    : Node("velocity-pid", from_hz(p.common.rate_hz)),
      p_(p),
      pid_(p.pid),
      arbiter_(p.arbiter),
      odom_fresh_(from_seconds(p.common.odometry_timeout_s)),
      setpoint_fresh_(from_seconds(p.common.input_timeout_s)),
      manual_fresh_(from_seconds(p.common.input_timeout_s)),
      progress_fresh_(from_seconds(p.common.input_timeout_s)),
      alloc_fresh_(from_seconds(p.common.allocation_timeout_s)),
      mode_(p.arbiter.default_mode),
      station_fresh_(from_seconds(p.common.input_timeout_s)),
      command_fresh_(from_seconds(p.common.allocation_timeout_s)),
      blend_(p.common.blend_s) {
  subscribe(channels::kWrenchStation, &VelocityPidNode::on_station_wrench);
  subscribe(channels::kOdometry, &VelocityPidNode::on_odometry);
  subscribe(channels::kVelocitySetpoint, &VelocityPidNode::on_setpoint);
  subscribe(channels::kManualVelocity, &VelocityPidNode::on_manual);
  subscribe(channels::kArmState, &VelocityPidNode::on_arm_state);
  rejected_station_ = &counter("rejected.manual_velocity.station");
  subscribe(channels::kMode, &VelocityPidNode::on_mode);
  subscribe(channels::kPathProgress, &VelocityPidNode::on_progress);
  subscribe(channels::kAllocationStatus, &VelocityPidNode::on_allocation);
  subscribe(channels::kThrusterCommand, &VelocityPidNode::on_thruster_command);
  subscribe(channels::kVehicleStatus, &VelocityPidNode::on_vehicle_status);
  advertise<wrench_t>(channels::kWrenchVelocity);
  advertise<arbitration_t>(channels::kArbitration);
  advertise<pid_terms_t>(channels::kPidVelocity);
  nan_odometry_ = &counter("rejected.odometry.nan");
  bad_setpoint_ = &counter("rejected.setpoint.invalid");
  bad_manual_ = &counter("rejected.manual.invalid");
  bad_progress_ = &counter("rejected.progress.invalid");
  bad_mode_ = &counter("rejected.mode.invalid");
  bad_station_wrench_ = &counter("rejected.wrench_station.nan");
  // Strings sized once, so a mode change allocates nothing (autonomy_alloc_test): the reason
  // (arbitration and status line) and the heartbeat's status.
  arb_.reason.reserve(Arbiter::kMaxReasonLength);
  reason_.reserve(Arbiter::kMaxReasonLength);
  set_health(heartbeat_t::STATE_OK, std::string(Arbiter::kMaxReasonLength, ' '));
  set_health(heartbeat_t::STATE_OK, "starting");
}

std::int64_t& VelocityPidNode::first_use(std::int64_t*& c, const char* name) {
  // Made on the first rejection, so the heartbeat of a run with good input is unchanged.
  if (c == nullptr) c = &counter(name);
  return *c;
}

void VelocityPidNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(odom_fresh_, m.utime, now, "odometry")) return;
  // The whole message against its contract (core/message_checks.hpp): non-finite values count
  // under rejected.odometry.nan, the rest (angles out of range, covariance size) under .range.
  if (const char* why = checks::check(m)) {
    reject(std::string_view(why).ends_with(".nan")
               ? *nan_odometry_
               : first_use(range_odometry_, "rejected.odometry.range"));
    return;
  }
  // Without a valid velocity and attitude the message is not taken: the odometry goes stale.
  odom_invalid_ = (m.valid & kNeeds) != kNeeds;
  estimate_.on_message(odom_invalid_, now);
  if (odom_invalid_) {
    ++first_use(invalid_odometry_, "odometry.invalid");
    return;
  }
  odom_ = m;
  odom_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_setpoint(const velocity_setpoint_t& m, TimeUs now) {
  if (!on_time(setpoint_fresh_, m.utime, now, "velocity_setpoint")) return;
  // Its contract (core/message_checks.hpp): a known frame, velocities within 10 m/s, the heading
  // finite and, when valid, in (-pi, pi].
  if (checks::check(m) != nullptr) {
    reject(*bad_setpoint_);
    return;
  }
  setpoint_ = m;
  setpoint_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_arm_state(const arm_state_t& m, TimeUs now) {
  // Only the station in control matters here; freshness and arming are the mixer's and the ESC's.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "arm_state")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.arm_state.invalid"));  // made on first use
    return;
  }
  stations_.on_arm_state(m);
}

void VelocityPidNode::on_manual(const manual_velocity_cmd_t& m, TimeUs now) {
  if (!on_time(manual_fresh_, m.utime, now, "manual_velocity")) return;
  if (!stations_.allows(m.station)) {  // another station's stick: not ours to follow
    reject(*rejected_station_);
    return;
  }
  // Its contract: velocity within 10 m/s, a known yaw mode, yaw rate within 5 rad/s, heading in
  // (-pi, pi], yaw torque within 1e4 N m.
  if (checks::check(m) != nullptr) {
    reject(*bad_manual_);
    return;
  }
  manual_ = m;
  manual_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_mode(const controller_mode_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kEventMaxAgeUs, "mode")) return;  // a stopped process's queue
  if (checks::check(m) != nullptr) {                           // an unknown mode
    reject(*bad_mode_);
    return;
  }
  mode_ = m.mode;
  is_translation_ = m.is_translation;
}

void VelocityPidNode::on_progress(const path_progress_t& m, TimeUs now) {
  if (!on_time(progress_fresh_, m.utime, now, "path_progress")) return;
  // Its contract: segment >= -1, n_waypoints >= 0, errors finite, distance to goal >= 0.
  if (checks::check(m) != nullptr) {
    reject(*bad_progress_);
    return;
  }
  progress_ = m;
  progress_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_allocation(const allocation_status_t& m, TimeUs now) {
  if (!on_time(alloc_fresh_, m.utime, now, "allocation")) return;
  if (checks::check(m) != nullptr) {  // unknown source, NaN, scale outside [0, 1], ...
    reject(first_use(bad_allocation_, "rejected.allocation.invalid"));
    return;
  }
  alloc_ = m;
  alloc_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_station_wrench(const wrench_t& m, TimeUs now) {
  if (!on_time(station_fresh_, m.utime, now, "wrench_station")) return;
  // Its contract (core/message_checks.hpp): a known source, each component within +-1e5 (a
  // 1e300 wrench would otherwise start the hand-over blend). Dropped: the last good one (or
  // none) stays in force. Non-finite under .nan, the rest under .range.
  if (checks::check(m) != nullptr) {
    reject(all_finite(m.tau) ? first_use(range_station_wrench_, "rejected.wrench_station.range")
                             : *bad_station_wrench_);
    return;
  }
  station_wrench_ = m;
  station_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_thruster_command(const thruster_command_t& m, TimeUs now) {
  if (!on_time(command_fresh_, m.utime, now, "thruster_command")) return;
  if (checks::check(m) != nullptr) {  // unknown source or gate, commands out of [-1, 1]
    reject(first_use(bad_command_, "rejected.thruster_command.invalid"));
    return;
  }
  command_gate_ = m.gate;
  command_source_ = m.source;
  command_fresh_.mark(now, m.utime, clock_offset());
}

void VelocityPidNode::on_vehicle_status(const vehicle_status_t& m, TimeUs now) {
  // tiller-failsafe's verdict. It has no freshness limit: the last action stays in force (a
  // failsafe that stops reporting does not end its hold); a queued old one is refused.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "vehicle_status")) return;
  if (checks::check(m) != nullptr) {
    reject(first_use(bad_status_, "rejected.vehicle_status.invalid"));
    return;
  }
  failsafe_hold_ =
      m.action == vehicle_status_t::ACTION_HOLD || m.action == vehicle_status_t::ACTION_RETURN;
}

void VelocityPidNode::publish_wrench(TimeUs now, bool valid, double x, double y, double n) {
  wrench_t w{};
  w.utime = now;
  w.source = wrench_t::SOURCE_VELOCITY_PID;
  w.valid = valid;
  w.tau[0] = x;
  w.tau[1] = y;
  w.tau[5] = n;
  publish(channels::kWrenchVelocity, w);
  last_wrench_ = w;
}

void VelocityPidNode::on_tick(TimeUs now) {
  // 1. The arbitration.
  ArbiterInput ai;
  ai.mode = mode_;
  ai.progress_fresh = progress_fresh_.fresh(now);
  ai.path_active = progress_.path_id >= 0 && progress_.segment >= 0;
  ai.setpoint_fresh = setpoint_fresh_.fresh(now);
  ai.complete = progress_.complete;
  ai.distance_to_goal = progress_.distance_to_goal;
  ai.failsafe_hold = failsafe_hold_;
  decision_ = arbiter_.decide(ai);
  arbitration_t& arb = arb_;
  arb.utime = now;
  arb.mode = decision_.mode;
  arb.active_source = decision_.source;
  arb.is_translation = is_translation_;
  if (decision_.changed) {
    arb.reason = decision_.reason;
    reason_ = decision_.reason;
  }
  publish(channels::kArbitration, arb);

  const bool active = decision_.source == wrench_t::SOURCE_VELOCITY_PID;
  const bool entering = active && !was_active_;
  // A mode switch with the PID in control throughout (manual closed loop <-> waypointing: the
  // source stays VELOCITY_PID) changes whose setpoint it tracks: the integrator built on the
  // other command must not carry over, and the output must not step to the new command.
  const bool switching = active && was_active_ && decision_.mode != prev_mode_;
  if (!active) {
    pid_.reset();  // restart from zero on entry
    blend_.stop();
  } else if (entering) {
    // Taking over: blend from the wrench that was in force. From station keeping, its last
    // wrench; from the pilot's open-loop stick, what the mixer last achieved with it (the
    // allocation status is in newtons even for a normalised demand); else from what we had.
    const bool from_station = prev_source_ == wrench_t::SOURCE_STATION_KEEP &&
                              station_fresh_.fresh(now) && station_wrench_.valid;
    const bool from_manual = prev_source_ == wrench_t::SOURCE_MANUAL_DEMAND &&
                             alloc_fresh_.fresh(now) &&
                             alloc_.source == wrench_t::SOURCE_MANUAL_DEMAND;
    if (from_station) {
      blend_.start(now, {station_wrench_.tau[0], station_wrench_.tau[1], station_wrench_.tau[5]});
    } else if (from_manual) {
      blend_.start(now, {alloc_.achieved[0], alloc_.achieved[1], alloc_.achieved[5]});
    } else if (last_wrench_.valid) {
      blend_.start(now, {last_wrench_.tau[0], last_wrench_.tau[1], last_wrench_.tau[5]});
    }
  } else if (switching) {
    // Both ways: the pilot's closed-loop command goes through this same PID, so there is no
    // separate path to be authoritative through; blend from what we last published.
    pid_.reset();
    if (last_wrench_.valid) {
      blend_.start(now, {last_wrench_.tau[0], last_wrench_.tau[1], last_wrench_.tau[5]});
    } else {
      blend_.stop();
    }
  }
  was_active_ = active;
  prev_source_ = decision_.source;
  prev_mode_ = decision_.mode;

  // 2. The wrench.
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
      set_health(heartbeat_t::STATE_DEGRADED, odom_invalid_ ? kInvalidHolding : kHolding);
    } else if (invalid_neutral_) {
      // The estimator is alive and says its estimate is not good enough (estimate_watch.hpp): a
      // deliberate neutral, so the vehicle stays armed and carries on when it is valid again.
      publish_wrench(now, true, 0, 0, 0);
      set_health(heartbeat_t::STATE_DEGRADED, kInvalidNeutral);
    } else {
      // Invalid: no wrench to give (nothing to hold on). The mixer counts it as input lost:
      // neutral at once, and a disarm request after safety.disarm_after_s.
      publish_wrench(now, false, 0, 0, 0);
      set_health(heartbeat_t::STATE_DEGRADED, odom_invalid_ ? kInvalid : kNeutral);
    }
    last_odom_utime_ = -1;
    return;
  }

  if (invalid_neutral_) {
    // Valid again after a deliberate neutral: ramp from that zero wrench over blend_s.
    invalid_neutral_ = false;
    if (active) blend_.start(now, {0, 0, 0});
  }
  VelocityPidInput in;
  in.u = odom_.velocity[0];
  in.v = odom_.velocity[1];
  in.r = odom_.velocity[5];
  in.heading = wrap_pi(odom_.orientation[2]);
  in.dt = last_odom_utime_ < 0 ? 0.0 : to_seconds(odom_.utime - last_odom_utime_);
  last_odom_utime_ = odom_.utime;
  bool have_command = false;
  if (decision_.mode == controller_mode_t::MANUAL_CLOSED_LOOP) {
    have_command = true;  // stale or invalid manual command: hold still
    if (manual_fresh_.fresh(now) && manual_.valid) {
      in.u_sp = manual_.velocity[0];
      in.v_sp = manual_.velocity[1];
      switch (manual_.yaw_mode) {
        case manual_velocity_cmd_t::YAW_HEADING:
          in.yaw_mode = YawMode::kHeading;
          in.yaw_value = manual_.heading;
          break;
        case manual_velocity_cmd_t::YAW_TORQUE:
          in.yaw_mode = YawMode::kTorque;
          in.yaw_value = manual_.yaw_torque;
          break;
        default:
          in.yaw_mode = YawMode::kRate;
          in.yaw_value = manual_.yaw_rate;
      }
    } else {
      in.yaw_mode = YawMode::kRate;
      in.yaw_value = 0;
    }
  } else if (setpoint_fresh_.fresh(now) && setpoint_.active) {
    have_command = true;
    double vx = setpoint_.velocity[0], vy = setpoint_.velocity[1];
    if (setpoint_.frame == velocity_setpoint_t::FRAME_NED) {
      const double c = std::cos(in.heading), s = std::sin(in.heading);
      in.u_sp = c * vx + s * vy;
      in.v_sp = -s * vx + c * vy;
    } else {
      in.u_sp = vx;
      in.v_sp = vy;
    }
    in.yaw_mode = setpoint_.heading_valid ? YawMode::kHeading : YawMode::kRate;
    in.yaw_value = setpoint_.heading_valid ? setpoint_.target_heading : 0.0;
  }
  // Integrate only while in control, and not on the entry or mode-switch tick: the integrator is
  // exactly zero when the PID takes over (it was reset while standing by, or just now). And only
  // while the mixer applies this wrench (gate ACTIVE): reset while disarmed or waiting for a
  // start, so a start begins from zero integral; frozen otherwise.
  if (!active || entering || switching) in.dt = 0;
  const IntegratorRule rule = integrator_rule(command_fresh_.fresh(now), command_gate_,
                                              command_source_, wrench_t::SOURCE_VELOCITY_PID);
  if (rule == IntegratorRule::kReset) pid_.reset();
  const bool alloc_ok = alloc_fresh_.fresh(now) && alloc_.source == wrench_t::SOURCE_VELOCITY_PID;
  for (int k = 0; k < 3; ++k) {
    in.freeze[static_cast<std::size_t>(k)] =
        rule != IntegratorRule::kIntegrate ||
        (alloc_ok && (alloc_.axis_reduced[kAxis[k]] || alloc_.axis_unactuated[kAxis[k]]));
  }
  terms_ = have_command ? pid_.step(in) : PidTerms{};
  if (have_command && active) terms_.out = blend_.apply(now, terms_.out);
  if (decision_.source == wrench_t::SOURCE_STATION_KEEP && station_fresh_.fresh(now) &&
      station_wrench_.valid) {
    // Station keeping in force: track its wrench, so the hand-back has no step.
    publish_wrench(now, true, station_wrench_.tau[0], station_wrench_.tau[1],
                   station_wrench_.tau[5]);
  } else if (decision_.source == wrench_t::SOURCE_MANUAL_DEMAND && alloc_fresh_.fresh(now) &&
             alloc_.source == wrench_t::SOURCE_MANUAL_DEMAND) {
    // The pilot's stick in force: track what the mixer makes of it, so a mixer that switches to
    // us (on the arbitration, before this node's next wrench) sees no step.
    publish_wrench(now, true, alloc_.achieved[0], alloc_.achieved[1], alloc_.achieved[5]);
  } else {
    publish_wrench(now, have_command, terms_.out[0], terms_.out[1], terms_.out[2]);
  }

  pid_terms_t t{};
  t.utime = now;
  t.controller = "velocity";
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
  publish(channels::kPidVelocity, t);
  set_health(heartbeat_t::STATE_OK, reason_);
}

}  // namespace tiller::control
