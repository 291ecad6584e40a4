#include "teleop/teleop_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

#include <tiller/arm_request_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/mission_command_t.hpp>

#include "core/angles.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller {

double normalise_axis(int raw, bool trigger) {
  if (trigger) {
    return std::clamp((static_cast<double>(raw) + kJsAxisMax) / (2.0 * kJsAxisMax), 0.0, 1.0);
  }
  return std::clamp(static_cast<double>(raw) / kJsAxisMax, -1.0, 1.0);
}

double shape_axis(double x, double deadzone, double expo) {
  const double a = std::fabs(x);
  if (!(a > deadzone)) return 0.0;
  const double s = std::min((a - deadzone) / (1.0 - deadzone), 1.0);
  const double y = (1.0 - expo) * s + expo * s * s * s;
  return x < 0 ? -y : y;
}

TeleopNode::TeleopNode(TeleopParams params, Input input)
    : Node(params.node_name, params.period),
      p_(std::move(params)),
      input_(input),
      gain_(p_.gain_initial),
      mode_(p_.initial_mode),
      translation_(p_.initial_translation),
      odom_fresh_(p_.odometry_timeout) {
  device_ = p_.device_path.empty() ? p_.device_name : p_.device_path;
  if (input_ == Input::replay) subscribe(channels::kJoystick, &TeleopNode::on_joystick);
  subscribe(channels::kOdometry, &TeleopNode::on_odometry);
  subscribe(channels::kArmState, &TeleopNode::on_arm_state);
  subscribe(channels::kMode, &TeleopNode::on_mode);
  if (input_ == Input::device) advertise<joystick_state_t>(channels::kJoystick);
  advertise<manual_demand_t>(channels::kManualDemand);
  advertise<manual_velocity_cmd_t>(channels::kManualVelocity);
  advertise<controller_mode_t>(channels::kMode);
  advertise<arm_request_t>(channels::kArmRequest);
  advertise<mission_command_t>(channels::kMissionCommand);
  rejected_state_ = &counter("rejected.joystick.malformed");
  bad_js_events_ = &counter("rejected.js_event.bad");
  rejected_odom_ = &counter("rejected.odometry.nan");
  disconnects_ = &counter("joystick.disconnects");
  presses_ = &counter("buttons.presses");
  bounces_ = &counter("buttons.bounces_ignored");
  reinits_ = &counter("joystick.reinit");
  js_msg_.device = device_;
  js_msg_.connected = false;
  js_msg_.n_axes = 0;
  js_msg_.n_buttons = 0;
  demand_msg_.valid = false;
  demand_msg_.station = p_.station;
  velocity_msg_.valid = false;
  velocity_msg_.station = p_.station;
  js_msg_.late_inits = 0;
  update_health();
}

void TeleopNode::feed(const joystick_state_t& state, TimeUs now) {
  process(state, now);
}

bool TeleopNode::note_bad_js_events(std::int64_t total) {
  const bool grew = total > *bad_js_events_;
  while (*bad_js_events_ < total) reject(*bad_js_events_);
  return grew;
}

void TeleopNode::on_joystick(const joystick_state_t& s, TimeUs now) {
  process(s, now);
}

void TeleopNode::on_odometry(const odometry_t& o, TimeUs now) {
  // The whole message is checked against its contract (core/message_checks.hpp), not only the
  // yaw: non-finite values count under rejected.odometry.nan, the rest under .range.
  if (!on_time(odom_fresh_, o.utime, now, "odometry")) return;
  if (const char* why = checks::check(o)) {
    if (std::string_view(why).ends_with(".nan")) {
      reject(*rejected_odom_);
    } else {
      if (!rejected_odom_range_) rejected_odom_range_ = &counter("rejected.odometry.range");
      reject(*rejected_odom_range_);
    }
    return;
  }
  // Heading hold needs the attitude only (an ROV without a position source still has it).
  if (!(o.valid & odometry_t::VALID_ATTITUDE)) {
    ++counter("odometry.invalid");  // made on first use
    return;
  }
  heading_ = o.orientation[2];  // in (-pi, pi] by the check
  odom_fresh_.mark(now, o.utime, clock_offset());
}

void TeleopNode::on_arm_state(const arm_state_t& a, TimeUs now) {
  // The vehicle's clock may be out of step with this station's either way (two computers): its
  // arm state counts within kArmStateSkewUs of this clock, ahead or behind; what is older (a
  // stopped process's queue) or further ahead is counted and dropped.
  if (a.utime < now - kArmStateSkewUs || a.utime > now + kArmStateSkewUs) {
    reject(counter("rejected.arm_state.skew"));  // made on first use
    return;
  }
  if (checks::check(a) != nullptr) {
    reject(counter("rejected.arm_state.invalid"));  // made on first use
    return;
  }
  armed_ = a.armed;
  arm_known_ = true;
  boot_nonce_ = a.boot_nonce;
  // Fresh by arrival, not by its stamp: the topside's clock may be out of step with the
  // vehicle's, and what the pilot must see is the vehicle's own state (on_time above refuses
  // only what is beyond the skew any signed message can have).
  arm_fresh_.mark(now, now, clock_offset());
  const bool told = a.controller != controller_ || a.reason != vehicle_reason_;
  if (a.controller != controller_) controller_ = a.controller;
  if (a.reason != vehicle_reason_) vehicle_reason_ = a.reason;
  if ((armed_ ? 1 : 0) != arm_shown_ || told) {
    update_health();
    publish_heartbeat_now(now);  // the pilot learns a refusal or a takeover at once
  }
}

void TeleopNode::on_mode(const controller_mode_t& m, TimeUs now) {
  // A mode command from another source (`tiller-rov-control --mode`, the cockpit) becomes the
  // pilot's mode, so this teleop's repeats carry it instead of undoing it.
  if (m.source == "teleop") return;  // our own
  if (!on_time(m.utime, now, kEventMaxAgeUs, "mode")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.mode.invalid"));  // made on first use
    return;
  }
  if (m.mode == mode_ && m.is_translation == translation_) return;
  mode_ = m.mode;
  translation_ = m.is_translation;
  last_mode_sent_ = now;  // the next repeat a period from now
  update_health();
}

void TeleopNode::process(const joystick_state_t& s, TimeUs now) {
  // Only the first n_axes / n_buttons entries count: a message decoded into a reused object
  // keeps the previous arrays when its count is 0 (lcm-gen resizes only for a count > 0).
  if (checks::check(s) != nullptr ||  // counts and axis values (-32767..32767)
      static_cast<int>(s.axes.size()) < s.n_axes ||
      static_cast<int>(s.buttons.size()) < s.n_buttons) {
    reject(*rejected_state_);
    return;
  }
  if (input_ == Input::device) {
    js_msg_.utime = now;
    js_msg_.connected = s.connected;
    js_msg_.n_axes = s.n_axes;
    js_msg_.axes.assign(s.axes.begin(), s.axes.begin() + s.n_axes);
    js_msg_.n_buttons = s.n_buttons;
    js_msg_.buttons.assign(s.buttons.begin(), s.buttons.begin() + s.n_buttons);
    js_msg_.late_inits = s.late_inits;
    if (!s.connected) std::fill(js_msg_.axes.begin(), js_msg_.axes.end(), 0);
    if (!s.connected) std::fill(js_msg_.buttons.begin(), js_msg_.buttons.end(), false);
  }
  apply_state(s, now);
  // The raw state goes out after the demand, so the demand is the first packet on the wire.
  if (input_ == Input::device) publish(channels::kJoystick, js_msg_);
}

void TeleopNode::apply_state(const joystick_state_t& s, TimeUs now) {
  if (!s.connected) {
    if (connected_) {
      ++*disconnects_;
      connected_ = false;
      centred_ = false;
      compute_demand();
      publish_outputs(now);  // neutral at once, not at the next tick
      update_health();
      publish_heartbeat_now(now);  // and say so at once, not at the next 1 Hz heartbeat
    }
    return;
  }

  if (connected_ && s.late_inits != late_inits_) device_reinit(now);
  late_inits_ = s.late_inits;
  const std::size_t nb = static_cast<std::size_t>(s.n_buttons);
  raw_axes_.assign(s.axes.begin(), s.axes.begin() + s.n_axes);
  if (!connected_) {
    connected_ = true;
    centred_ = false;
    holding_ = false;
    raw_buttons_.assign(s.buttons.begin(), s.buttons.begin() + s.n_buttons);
    stable_ = raw_buttons_;
    inhibited_ = raw_buttons_;  // held at connection: not a press
    raw_since_.assign(nb, now);
    update_health();
  } else {
    update_buttons(now);  // a change stable for the debounce time counts even if it ends now
    if (raw_buttons_.size() < nb) {
      raw_buttons_.resize(nb, false);
      stable_.resize(nb, false);
      inhibited_.resize(nb, false);
      raw_since_.resize(nb, now);
    }
    for (std::size_t i = 0; i < nb; ++i) {
      const bool b = s.buttons[i] != 0;
      if (b == raw_buttons_[i]) continue;
      // A change back to the debounced state before it was accepted was a bounce.
      if (b == stable_[i] && now - raw_since_[i] < p_.debounce) ++*bounces_;
      raw_buttons_[i] = b;
      raw_since_[i] = now;
    }
  }
  update_buttons(now);
  const bool changed = compute_demand();
  if (changed && p_.publish_on_change) publish_outputs(now);
}

void TeleopNode::device_reinit(TimeUs now) {
  // The device re-sent its start-up state after ordinary input: whatever it says now is not a
  // deliberate move. As on a reconnection: neutral at once, held buttons ignored until
  // released, and a centred stick before anything counts; and ask the vehicle to disarm.
  ++*reinits_;
  connected_ = false;  // apply_state() then runs its connection path with this state
  centred_ = false;
  compute_demand();
  publish_outputs(now);
  send_arm_request(false, false, now);
  update_health();
  publish_heartbeat_now(now);
}

void TeleopNode::send_arm_request(bool arm, bool takeover, TimeUs now) {
  arm_request_t r;
  r.utime = now;
  r.arm = arm;
  r.source = "teleop";
  r.boot_nonce = boot_nonce_;
  r.station = p_.station;
  r.takeover = takeover;
  publish(channels::kArmRequest, r);
}

void TeleopNode::update_buttons(TimeUs now) {
  if (!connected_) return;
  for (std::size_t i = 0; i < raw_buttons_.size(); ++i) {
    if (raw_buttons_[i] == stable_[i] || now - raw_since_[i] < p_.debounce) continue;
    stable_[i] = raw_buttons_[i];
    if (!stable_[i]) {
      inhibited_[i] = false;
    } else if (!inhibited_[i]) {
      on_press(static_cast<int>(i), now);
    }
  }
}

void TeleopNode::on_press(int b, TimeUs now) {
  ++*presses_;
  const TeleopButtons& k = p_.buttons;
  if (b == k.arm || b == k.disarm || b == k.takeover) {
    send_arm_request(b != k.disarm, b == k.takeover, now);
  }
  bool mode_changed = false;
  if (b == k.mode_open_loop) mode_ = controller_mode_t::MANUAL_OPEN_LOOP, mode_changed = true;
  if (b == k.mode_closed_loop) mode_ = controller_mode_t::MANUAL_CLOSED_LOOP, mode_changed = true;
  if (b == k.mode_autonomous) mode_ = controller_mode_t::WAYPOINTING, mode_changed = true;
  if (b == k.toggle_translation) translation_ = !translation_, mode_changed = true;
  const std::pair<int, std::int8_t> rov_modes[] = {
      {k.mode_stabilise, controller_mode_t::STABILISE},
      {k.mode_depth_hold, controller_mode_t::DEPTH_HOLD},
      {k.mode_heading_hold, controller_mode_t::HEADING_HOLD},
      {k.mode_rate, controller_mode_t::RATE},
      {k.mode_surface, controller_mode_t::SURFACE},
      {k.mode_position_hold, controller_mode_t::POSITION_HOLD}};
  for (const auto& [button, mode] : rov_modes)
    if (b == button) mode_ = mode, mode_changed = true;
  if (mode_changed) publish_mode(now);
  if (b == k.mode_autonomous) {
    // Pressing the autonomous button is the operator's go for the autonomy (docs/safety.md): an
    // event, sent once, its id the press time.
    mission_command_t c;
    c.utime = now;
    c.command_id = now > 0 ? now : 1;
    c.command = mission_command_t::RESUME;
    c.source = "teleop";
    publish(channels::kMissionCommand, c);
  }
  if (b == k.gain_up || b == k.gain_down) {
    const double g = gain_ + (b == k.gain_up ? p_.gain_step : -p_.gain_step);
    constexpr double kSlack = 1e-9;  // steps of 0.25 land on the limits exactly or nearly
    if (p_.gain_wrap && g > p_.gain_max + kSlack && gain_ >= p_.gain_max - kSlack)
      gain_ = p_.gain_min;
    else if (p_.gain_wrap && g < p_.gain_min - kSlack && gain_ <= p_.gain_min + kSlack)
      gain_ = p_.gain_max;
    else
      gain_ = std::clamp(g, p_.gain_min, p_.gain_max);
  }
  update_health();
}

bool TeleopNode::compute_demand() {
  std::array<double, 6> d{};
  bool valid = false;
  if (connected_) {
    auto axis_raw = [&](int a) {
      return a < static_cast<int>(raw_axes_.size()) ? raw_axes_[a] : 0;
    };
    auto held = [&](int b) {
      return b >= 0 && b < static_cast<int>(stable_.size()) && stable_[b] && !inhibited_[b];
    };
    if (!centred_) {
      bool c = true;
      for (const TeleopAxis& a : p_.axes) {
        // An axis the device has not reported yet is not centred: its position is unknown (the
        // start-up state can arrive over several reads).
        if (a.axis >= static_cast<int>(raw_axes_.size())) {
          c = false;
          continue;
        }
        const double x = normalise_axis(axis_raw(a.axis), a.trigger);
        if (std::fabs(x) > a.deadzone) c = false;
      }
      for (const TeleopButtonAxis& a : p_.button_axes) {
        if (held(a.plus) || held(a.minus)) c = false;
      }
      if (c) {
        centred_ = true;
        update_health();
      }
    }
    if (centred_) {
      valid = true;
      for (const TeleopAxis& a : p_.axes) {
        const double x = normalise_axis(axis_raw(a.axis), a.trigger);
        d[static_cast<std::size_t>(a.dof)] += a.sign * shape_axis(x, a.deadzone, a.expo) * a.gain;
      }
      for (const TeleopButtonAxis& a : p_.button_axes) {
        d[static_cast<std::size_t>(a.dof)] +=
            a.gain * ((held(a.plus) ? 1.0 : 0.0) - (held(a.minus) ? 1.0 : 0.0));
      }
      for (double& v : d) v = std::clamp(v * gain_, -1.0, 1.0);
    }
  }
  const bool changed = d != demand_ || valid != valid_;
  demand_ = d;
  valid_ = valid;
  return changed;
}

void TeleopNode::publish_outputs(TimeUs now) {
  demand_msg_.utime = now;
  std::copy(demand_.begin(), demand_.end(), demand_msg_.demand);
  demand_msg_.valid = valid_;
  publish(channels::kManualDemand, demand_msg_);

  manual_velocity_cmd_t& v = velocity_msg_;
  v.utime = now;
  for (int i = 0; i < 3; ++i)
    v.velocity[i] =
        demand_[static_cast<std::size_t>(i)] * p_.max_speed[static_cast<std::size_t>(i)];
  const double n = demand_[5];
  v.yaw_rate = 0.0;
  v.heading = 0.0;
  v.yaw_torque = 0.0;
  switch (p_.yaw_mode) {
    case YawMode::rate:
      v.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
      v.yaw_rate = n * p_.max_yaw_rate;
      break;
    case YawMode::torque:
      v.yaw_mode = manual_velocity_cmd_t::YAW_TORQUE;
      v.yaw_torque = n * p_.max_yaw_torque;
      break;
    case YawMode::heading_hold:
      if (n != 0.0 || !valid_ || !odom_fresh_.fresh(now)) {
        holding_ = false;
        v.yaw_mode = manual_velocity_cmd_t::YAW_RATE;
        v.yaw_rate = n * p_.max_yaw_rate;
      } else {
        if (!holding_) held_heading_ = heading_;
        holding_ = true;
        v.yaw_mode = manual_velocity_cmd_t::YAW_HEADING;
        v.heading = held_heading_;
      }
      break;
  }
  v.valid = valid_;
  publish(channels::kManualVelocity, v);
}

void TeleopNode::publish_mode(TimeUs now) {
  controller_mode_t m;
  m.utime = now;
  m.mode = mode_;
  m.is_translation = translation_;
  m.source = "teleop";
  publish(channels::kMode, m);
  mode_sent_ = true;
  last_mode_sent_ = now;
}

void TeleopNode::on_tick(TimeUs now) {
  if (arm_known_ && !arm_fresh_.fresh(now)) {
    arm_known_ = false;  // tiller-esc silent: say so rather than show an old state
    update_health();
  }
  if (input_ == Input::device) {
    js_msg_.utime = now;
    publish(channels::kJoystick, js_msg_);
  }
  update_buttons(now);
  compute_demand();
  publish_outputs(now);
  if (!mode_sent_ || (p_.mode_repeat > 0 && now - last_mode_sent_ >= p_.mode_repeat)) {
    publish_mode(now);
  }
}

void TeleopNode::shutdown(TimeUs now) {
  // Stopping (SIGINT, SIGTERM): a neutral, invalid demand at once, so the mixer does not keep
  // using the last one until it goes stale.
  connected_ = false;
  centred_ = false;
  compute_demand();
  publish_outputs(now);
}

void TeleopNode::update_health() {
  const int arm = arm_known_ ? (armed_ ? 1 : 0) : -1;
  arm_shown_ = arm;
  std::string arm_text = arm < 0 ? "; arm state unknown" : arm ? "; ARMED" : "; disarmed";
  if (arm >= 0) {
    if (armed_ && !controller_.empty())
      arm_text += controller_ == p_.station ? " (this station in control)"
                                            : " (station " + controller_ + " in control)";
    if (!vehicle_reason_.empty()) arm_text += "; vehicle: " + vehicle_reason_;
  }
  static const char* const mode_names[9] = {
      "open-loop manual", "closed-loop manual", "autonomous", "stabilise",
      "depth hold",       "heading hold",       "rate",       "surface",
      "position hold"};
  const char* mode = mode_ >= 0 && mode_ <= 8 ? mode_names[mode_] : "?";
  char buf[512];
  if (!connected_) {
    std::snprintf(buf, sizeof buf, "joystick absent (%s)%s", device_.c_str(), arm_text.c_str());
    set_health(heartbeat_t::STATE_DEGRADED, buf);
  } else if (!centred_) {
    std::snprintf(buf, sizeof buf, "joystick connected, waiting for the stick to be centred%s",
                  arm_text.c_str());
    set_health(heartbeat_t::STATE_DEGRADED, buf);
  } else {
    std::snprintf(buf, sizeof buf, "joystick ok; mode %s%s; gain %.2f%s", mode,
                  translation_ ? " (translation)" : "", gain_, arm_text.c_str());
    set_health(heartbeat_t::STATE_OK, buf);
  }
}

}  // namespace tiller
