#include "mixer/mixer_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string_view>

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>

#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller {
namespace {

TimeUs seconds_key(const config::Value& v, const char* key, double fallback) {
  return from_seconds(v.number_or(key, fallback, {1e-3, 60.0}));
}

std::int8_t source_from_name(const std::string& s) {
  if (s == "manual_demand") return wrench_t::SOURCE_MANUAL_DEMAND;
  if (s == "velocity_pid") return wrench_t::SOURCE_VELOCITY_PID;
  if (s == "station_keep") return wrench_t::SOURCE_STATION_KEEP;
  if (s == "rov_control") return wrench_t::SOURCE_ROV_CONTROL;
  return wrench_t::SOURCE_NONE;
}

}  // namespace

MixerParams load_mixer_params(const config::Value& root) {
  namespace fs = std::filesystem;
  MixerParams p;
  const config::Value vk = root.at("vehicle");
  const std::string rel = vk.as_string();
  // Absolute; else beside this config; else relative to one of its parent folders (so a
  // repository-root path like config/vehicles/x.yaml works from any directory); else the
  // current directory.
  fs::path chosen;
  if (fs::path(rel).is_absolute()) {
    chosen = rel;
  } else {
    for (fs::path dir = fs::absolute(root.file()).parent_path(); chosen.empty();
         dir = dir.parent_path()) {
      if (fs::exists(dir / rel)) chosen = dir / rel;
      if (dir == dir.root_path() || dir.empty()) break;
    }
    if (chosen.empty()) chosen = rel;
  }
  if (!fs::exists(chosen))
    vk.fail(
        "a vehicle file (absolute, or relative to this config's folder, one of its parents or "
        "the current directory); not found: " +
        rel);
  p.vehicle_file = chosen.lexically_normal().string();
  p.rate_hz = root.number_or("rate_hz", 50.0, {1.0, 1000.0});
  p.fallback_source = source_from_name(
      root.choice_or("fallback_source", "manual_demand",
                     {"manual_demand", "velocity_pid", "station_keep", "rov_control", "none"}));
  p.publish_every_input = root.choice_or("publish_at_once", "active_source",
                                         {"active_source", "every_input"}) == "every_input";
  if (auto f = root.find("freshness")) {
    p.manual_timeout_us = seconds_key(*f, "manual_demand_s", 0.5);
    p.wrench_timeout_us = seconds_key(*f, "wrench_s", 0.5);
    p.arbitration_timeout_us = seconds_key(*f, "arbitration_s", 1.0);
    p.arm_timeout_us = seconds_key(*f, "arm_state_s", 0.5);
  }
  if (auto f = root.find("safety")) {
    p.disarm_after_us = from_seconds(f->number_or("disarm_after_s", 3.0, {0.1, 600.0}));
  }
  if (auto f = root.find("thruster_test")) {
    p.test_max_command = f->number_or("max_command", 0.15, {0.0, 0.3});
    p.test_request_us = from_seconds(f->number_or("request_s", 0.5, {0.05, 2.0}));
    p.test_max_duration_us = from_seconds(f->number_or("max_duration_s", 10.0, {0.5, 60.0}));
    if (auto v = f->find("senders")) {
      p.test_senders.clear();
      for (const auto& item : v->items()) {
        const std::string name = item.as_string();
        if (name.empty() || name.size() > 16)
          item.fail("a node name of 1 to 16 characters (the sender in a signed message)");
        p.test_senders.push_back(name);
      }
      if (p.test_senders.empty()) v->fail("a list of at least one sender, e.g. [cockpit]");
    }
  }
  return p;
}

std::int8_t select_source(bool arbitration_fresh, std::int8_t arbitration_source,
                          std::int8_t fallback_source, bool failsafe_fresh) {
  if (failsafe_fresh) return wrench_t::SOURCE_FAILSAFE;
  return arbitration_fresh ? arbitration_source : fallback_source;
}

MixerNode::MixerNode(const MixerParams& params, const Vehicle& vehicle)
    : Node("mixer", from_hz(params.rate_hz)),
      p_(params),
      alloc_(std::make_unique<Allocator>(vehicle)),
      manual_fresh_(params.manual_timeout_us),
      arb_fresh_(params.arbitration_timeout_us),
      arm_fresh_(params.arm_timeout_us),
      test_fresh_(params.test_request_us),
      gate_([&] {
        safety::GateParams g;
        g.disarm_after_us = params.disarm_after_us;
        g.test_max_command = params.test_max_command;
        g.test_max_duration_us = params.test_max_duration_us;
        return g;
      }()) {
  velocity_.fresh.set_limit(p_.wrench_timeout_us);
  station_.fresh.set_limit(p_.wrench_timeout_us);
  rov_.fresh.set_limit(p_.wrench_timeout_us);
  failsafe_.fresh.set_limit(p_.wrench_timeout_us);
  subscribe(channels::kManualDemand, &MixerNode::on_manual);
  subscribe(channels::kWrenchVelocity, &MixerNode::on_wrench_velocity);
  subscribe(channels::kWrenchStation, &MixerNode::on_wrench_station);
  subscribe(channels::kWrenchRov, &MixerNode::on_wrench_rov);
  subscribe(channels::kWrenchFailsafe, &MixerNode::on_wrench_failsafe);
  subscribe(channels::kArbitration, &MixerNode::on_arbitration);
  subscribe(channels::kArmState, &MixerNode::on_arm_state);
  subscribe(channels::kMissionCommand, &MixerNode::on_mission_command);
  subscribe(channels::kThrusterTest, &MixerNode::on_thruster_test);
  subscribe(channels::kVehicleStatus, &MixerNode::on_vehicle_status);
  subscribe(channels::kPower, &MixerNode::on_power);
  supply_stale_ = &counter("supply_voltage.stale");
  accept_only_from(channels::kThrusterTest, p_.test_senders);
  advertise<thruster_command_t>(channels::kThrusterCommand);
  advertise<allocation_status_t>(channels::kAllocationStatus);
  advertise<arm_request_t>(channels::kArmRequest);  // disarm requests only
  rej_manual_ = &counter("rejected.manual_demand.range");
  rej_station_ = &counter("rejected.manual_demand.station");
  rej_wrench_ = &counter("rejected.wrench.range");
  rej_arb_ = &counter("rejected.arbitration.source");
  rej_mission_ = &counter("rejected.mission_command.invalid");
  held_neutral_ = &counter("neutral.safety_gate");
  disarm_requests_ = &counter("safety.disarm_requests");
  cmd_.hold.reserve(192);  // the longest hold: a test refusal naming the failsafe (160)
  neutral_disarmed_ = &counter("neutral.disarmed");
  neutral_no_input_ = &counter("neutral.no_valid_input");
  rej_test_ = &counter("rejected.thruster_test.invalid");
  test_started_ = &counter("thruster_test.started");
  test_refused_ = &counter("thruster_test.refused");
  const int n = alloc_->size();
  cmd_.n_thrusters = n;
  status_.n_thrusters = n;
  cmd_.command.assign(static_cast<std::size_t>(n), 0.0);
  status_.saturated.assign(static_cast<std::size_t>(n), false);
  for (const Thruster& t : vehicle.thrusters) {
    cmd_.names.push_back(t.name);
    status_.names.push_back(t.name);
  }
  status_.strategy = alloc_->strategy_name();
  alloc_->neutral(result_);
  set_health(heartbeat_t::STATE_OK, "starting: disarmed, neutral");
}

MixerNode::MixerNode(const std::string& config_path)
    : MixerNode(
          [&] {
            const auto root = config::Value::load_file(config_path);
            MixerParams p = load_mixer_params(root);
            root.check_all_used();
            return p;
          }(),
          load_vehicle_file([&] {
            const auto root = config::Value::load_file(config_path);
            root.mark_used();
            return load_mixer_params(root).vehicle_file;
          }())) {}

std::int8_t MixerNode::source_now(TimeUs now) {
  return select_source(arb_fresh_.fresh(now), arb_source_, p_.fallback_source,
                       failsafe_.fresh.fresh(now));
}

// New input publishes at once only when it is the active source's: the command rate stays the
// active source's rate (plus the fixed rate), whatever the other feeds do.
void MixerNode::on_manual(const manual_demand_t& m, TimeUs now) {
  if (!on_time(manual_fresh_, m.utime, now, "manual_demand")) return;
  if (!stations_.allows(m.station)) {  // another station's stick: not ours to follow
    reject(*rej_station_);
    return;
  }
  if (!all_in_range(m.demand, -1.0, 1.0)) {
    manual_fresh_.reset();
    reject(*rej_manual_);
  } else if (!m.valid) {
    manual_fresh_.reset();  // the teleop says: nothing to say -> absent
  } else {
    for (int i = 0; i < 6; ++i) manual_(i) = m.demand[i];
    manual_fresh_.mark(now, m.utime, clock_offset());
  }
  if (p_.publish_every_input || source_now(now) == wrench_t::SOURCE_MANUAL_DEMAND) output(now);
}

void MixerNode::on_wrench(WrenchInput& in, std::int8_t source, const wrench_t& m, TimeUs now) {
  if (!on_time(in.fresh, m.utime, now,
               source == wrench_t::SOURCE_VELOCITY_PID   ? "wrench_velocity"
               : source == wrench_t::SOURCE_ROV_CONTROL  ? "wrench_rov"
               : source == wrench_t::SOURCE_STATION_KEEP ? "wrench_station"
                                                         : "wrench_failsafe"))
    return;
  const std::int8_t before = source_now(now);
  if (checks::check(m) != nullptr) {  // unknown source, NaN, beyond +-1e5
    in.fresh.reset();
    reject(*rej_wrench_);
  } else if (!m.valid) {
    in.fresh.reset();
  } else {
    for (int i = 0; i < 6; ++i) in.tau(i) = m.tau[i];
    in.fresh.mark(now, m.utime, clock_offset());
  }
  if (p_.publish_every_input || source_now(now) == source || source_now(now) != before) output(now);
}

void MixerNode::on_wrench_velocity(const wrench_t& m, TimeUs now) {
  on_wrench(velocity_, wrench_t::SOURCE_VELOCITY_PID, m, now);
}
void MixerNode::on_wrench_station(const wrench_t& m, TimeUs now) {
  on_wrench(station_, wrench_t::SOURCE_STATION_KEEP, m, now);
}
void MixerNode::on_wrench_rov(const wrench_t& m, TimeUs now) {
  on_wrench(rov_, wrench_t::SOURCE_ROV_CONTROL, m, now);
}
void MixerNode::on_wrench_failsafe(const wrench_t& m, TimeUs now) {
  on_wrench(failsafe_, wrench_t::SOURCE_FAILSAFE, m, now);
}

// Arbitration and arm state publish at once when they change what the mixer does (the active
// source; armed or not), not on every repetition.
void MixerNode::on_arbitration(const arbitration_t& m, TimeUs now) {
  // A refused arbitration (unknown source or mode) is dropped: the last good one stays in force
  // until it is stale. Making it absent would hand the thrusters to fallback_source (often the
  // pilot's stick) on one bad packet.
  if (!on_time(arb_fresh_, m.utime, now, "arbitration")) return;
  if (const char* why = checks::check(m)) {
    if (std::string_view(why) == "mode.unknown" && rej_arb_mode_ == nullptr)
      rej_arb_mode_ = &counter("rejected.arbitration.mode");  // on first use
    reject(std::string_view(why) == "mode.unknown" ? *rej_arb_mode_ : *rej_arb_);
    return;
  }
  const std::int8_t before = source_now(now);
  arb_source_ = m.active_source;
  arb_mode_ = m.mode;
  arb_fresh_.mark(now, m.utime, clock_offset());
  if (p_.publish_every_input || source_now(now) != before) output(now);
}

void MixerNode::on_arm_state(const arm_state_t& m, TimeUs now) {
  if (!on_time(arm_fresh_, m.utime, now, "arm_state")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.arm_state.invalid"));  // made on first use
    return;
  }
  const bool before = armed_ && arm_fresh_.fresh(now);
  armed_ = m.armed;
  session_ = m.session;
  stations_.on_arm_state(m);
  arm_fresh_.mark(now, m.utime, clock_offset());
  if (p_.publish_every_input || (armed_ && arm_fresh_.fresh(now)) != before) output(now);
}

void MixerNode::on_mission_command(const mission_command_t& m, TimeUs now) {
  // An operator's go is an event: one that waited in a stopped process's queue is too late.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "mission_command")) return;
  if (checks::check(m) != nullptr) {
    reject(*rej_mission_);
    return;
  }
  // Published at once only when it changes what the mixer does (a go while waiting, a release).
  bool act = false;
  if (m.command == mission_command_t::START || m.command == mission_command_t::RESUME) {
    act = gate_.operator_go(m.command_id, now) && gate_.state() == safety::GateState::kWaitNeutral;
  } else if (m.command == mission_command_t::RELEASE) {
    act = gate_.operator_release(m.command_id, now);
  }
  if (act) output(now);
}

void MixerNode::on_thruster_test(const thruster_test_t& m, TimeUs now) {
  if (!on_time(test_fresh_, m.utime, now, "thruster_test")) return;
  // Published at once only when it can change what the mixer does: a new press, or a running
  // test let go, changed or ended by a bad request (a repeat while held waits for the tick).
  const bool testing = gate_.state() == safety::GateState::kTest;
  if (checks::check(m) != nullptr) {
    reject(*rej_test_);
    if (testing) {  // a bad request ends a running test at once; otherwise it is only dropped
      test_fresh_.reset();
      output(now);
    }
    return;
  }
  const bool new_press = m.active && m.test_id != test_.id;
  const bool change = testing && (!m.active || m.test_id != test_.id ||
                                  m.thruster != test_.thruster || m.command != test_.command);
  test_.id = m.test_id;
  test_.thruster = m.thruster;
  test_.command = m.command;
  if (m.active) {
    test_fresh_.mark(now, m.utime, clock_offset());
  } else {
    test_fresh_.reset();
  }
  if (new_press || change) output(now);
}

void MixerNode::on_vehicle_status(const vehicle_status_t& m, TimeUs now) {
  // An event: one that waited in a stopped process's queue is too late. No freshness limit
  // after that: the last status stays in force.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "vehicle_status")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.vehicle_status.invalid"));  // made on first use
    return;
  }
  static constexpr const char* kActions[] = {"NONE",    "WARN",    "HOLD",   "RETURN",
                                             "SURFACE", "NEUTRAL", "DISARM", "RISE"};
  const bool was = failsafe_text_[0] != '\0';
  if (m.active != 0 || m.action > vehicle_status_t::ACTION_WARN) {
    const int a = m.action;  // checked: one of ACTION_*
    std::snprintf(failsafe_text_, sizeof failsafe_text_, "%s: %s",
                  a >= 0 && a < 8 ? kActions[a] : "?", m.reason.c_str());
  } else {
    failsafe_text_[0] = '\0';
  }
  // A running test ends at once when a failsafe becomes active.
  if (!was && failsafe_text_[0] != '\0' && gate_.state() == safety::GateState::kTest) output(now);
}

// The controller the source in control belongs to: the arbitration's mode when it is fresh,
// else what the fallback source is.
safety::Controller MixerNode::controller_now(TimeUs now) {
  // tiller-failsafe's wrench in force; or its hold, which is the only station keeping in a manual
  // mode (lib/control/arbiter.hpp).
  if (failsafe_.fresh.fresh(now)) return safety::Controller::kFailsafe;
  if (arb_fresh_.fresh(now) && arb_source_ == wrench_t::SOURCE_STATION_KEEP &&
      arb_mode_ != controller_mode_t::WAYPOINTING)
    return safety::Controller::kFailsafe;
  if (arb_fresh_.fresh(now)) {
    if (arb_source_ == wrench_t::SOURCE_NONE && arb_mode_ != controller_mode_t::WAYPOINTING)
      return safety::Controller::kNone;
    return arb_mode_ == controller_mode_t::WAYPOINTING ? safety::Controller::kAutonomy
                                                       : safety::Controller::kPilot;
  }
  switch (p_.fallback_source) {
    case wrench_t::SOURCE_MANUAL_DEMAND:
      return safety::Controller::kPilot;
    case wrench_t::SOURCE_NONE:
      return safety::Controller::kNone;
    default:
      return safety::Controller::kAutonomy;
  }
}

void MixerNode::request_disarm(const char* why, TimeUs now) {
  ++*disarm_requests_;
  arm_request_t r{};
  r.utime = now;
  r.arm = false;
  r.source = std::string("mixer (") + why + ")";
  publish(channels::kArmRequest, r);
}

void MixerNode::on_power(const power_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kSupplyStaleUs, "power")) return;
  if (checks::check(m) != nullptr) {
    reject(counter("rejected.power.invalid"));  // made on first use
    return;
  }
  if (!alloc_->voltage_dependent()) return;  // checked and counted all the same
  alloc_->set_supply_voltage(m.voltage);
  power_rx_ = now;
}

void MixerNode::on_tick(TimeUs now) {
  if (power_rx_ >= 0 && now - power_rx_ > kSupplyStaleUs) {
    alloc_->set_supply_voltage(1e9);  // clamped to the tables' highest voltage
    power_rx_ = -1;
    ++*supply_stale_;
  }
  output(now);
}

void MixerNode::shutdown(TimeUs now) {
  armed_ = false;
  output(now);
}

void MixerNode::output(TimeUs now) {
  const bool armed = armed_ && arm_fresh_.fresh(now);
  active_ = source_now(now);
  // The safety gate (lib/safety/intent_gate.hpp).
  safety::GateInput gi;
  gi.armed = armed;
  gi.session = session_;
  gi.controller = controller_now(now);
  gi.pilot_fresh = manual_fresh_.fresh(now);
  for (int i = 0; i < 6; ++i) gi.pilot[static_cast<std::size_t>(i)] = manual_(i);
  gi.source_fresh = (active_ == wrench_t::SOURCE_MANUAL_DEMAND && gi.pilot_fresh) ||
                    (active_ == wrench_t::SOURCE_VELOCITY_PID && velocity_.fresh.fresh(now)) ||
                    (active_ == wrench_t::SOURCE_STATION_KEEP && station_.fresh.fresh(now)) ||
                    (active_ == wrench_t::SOURCE_ROV_CONTROL && rov_.fresh.fresh(now)) ||
                    (active_ == wrench_t::SOURCE_FAILSAFE && failsafe_.fresh.fresh(now));
  gi.test = test_;
  gi.test.fresh = test_fresh_.fresh(now);
  gi.n_thrusters = alloc_->size();
  gi.failsafe = failsafe_text_[0] != '\0' ? failsafe_text_ : nullptr;
  const safety::GateState before = gate_.state();
  const std::int64_t refused_before = gate_.test_refusals();
  const safety::GateOutput g = gate_.step(gi, now);
  if (g.disarm) request_disarm(g.hold, now);
  const bool test = armed && g.state == safety::GateState::kTest;
  if (test && before != safety::GateState::kTest) ++*test_started_;
  *test_refused_ += gate_.test_refusals() - refused_before;
  bool ok = false;
  if (!armed) {
    ++*neutral_disarmed_;
  } else if (test) {
    // One thruster at the test's command, below; nothing allocated.
  } else if (!g.may_move) {
    ++*(g.state == safety::GateState::kInputLost ? neutral_no_input_ : held_neutral_);
  } else if (active_ == wrench_t::SOURCE_MANUAL_DEMAND && manual_fresh_.fresh(now)) {
    ok = alloc_->allocate_manual(manual_, result_);
  } else if (active_ == wrench_t::SOURCE_VELOCITY_PID && velocity_.fresh.fresh(now)) {
    ok = alloc_->allocate(velocity_.tau, result_);
  } else if (active_ == wrench_t::SOURCE_STATION_KEEP && station_.fresh.fresh(now)) {
    ok = alloc_->allocate(station_.tau, result_);
  } else if (active_ == wrench_t::SOURCE_ROV_CONTROL && rov_.fresh.fresh(now)) {
    ok = alloc_->allocate(rov_.tau, result_);
  } else if (active_ == wrench_t::SOURCE_FAILSAFE && failsafe_.fresh.fresh(now)) {
    ok = alloc_->allocate(failsafe_.tau, result_);
  } else {
    ++*neutral_no_input_;
  }
  if (!ok) alloc_->neutral(result_);
  // Fresh-to-stale transitions of every input feed the heartbeat's "stale" counter.
  const std::int64_t stale_now = manual_fresh_.stale_events() + velocity_.fresh.stale_events() +
                                 station_.fresh.stale_events() + rov_.fresh.stale_events() +
                                 failsafe_.fresh.stale_events() + arb_fresh_.stale_events() +
                                 arm_fresh_.stale_events();
  if (stale_now > stale_seen_) {
    count_stale(stale_now - stale_seen_);
    stale_seen_ = stale_now;
  }

  cmd_.utime = now;
  cmd_.armed = armed && (ok || test);
  cmd_.gate = static_cast<std::int8_t>(g.state);
  cmd_.arm_allowed = g.arm_allowed;
  cmd_.hold = g.hold;
  cmd_.source = ok ? active_ : wrench_t::SOURCE_NONE;
  for (int i = 0; i < result_.n; ++i)
    cmd_.command[static_cast<std::size_t>(i)] = ok ? result_.command[static_cast<std::size_t>(i)]
                                                : test && i == g.test_thruster ? g.test_command
                                                                               : 0.0;
  publish(channels::kThrusterCommand, cmd_);

  status_.utime = now;
  status_.source = cmd_.source;
  for (int ax = 0; ax < 6; ++ax) {
    const auto a = static_cast<std::size_t>(ax);
    status_.demanded[ax] = result_.demanded(ax);
    status_.achieved[ax] = result_.achieved(ax);
    status_.unallocated[ax] = result_.unallocated(ax);
    status_.axis_reduced[ax] = result_.axis_reduced[a];
    status_.axis_unactuated[ax] = result_.axis_unactuated[a];
  }
  status_.scale = result_.scale;
  for (int i = 0; i < result_.n; ++i)
    status_.saturated[static_cast<std::size_t>(i)] = result_.saturated[static_cast<std::size_t>(i)];
  publish(channels::kAllocationStatus, status_);

  // Disarmed, or armed and waiting for the source to show neutral, is a normal state (OK);
  // armed with the source's input missing is DEGRADED.
  const char* text = ok                  ? "allocating"
                     : !armed            ? "disarmed: neutral"
                     : test              ? "thruster test"
                     : g.hold[0] != '\0' ? g.hold
                                         : "armed, no valid input: neutral";
  const std::int8_t health = ok || test || !armed || g.state == safety::GateState::kWaitNeutral
                                 ? heartbeat_t::STATE_OK
                                 : heartbeat_t::STATE_DEGRADED;
  if (health != health_ || health_text_ != text) {
    health_ = health;
    health_text_ = text;  // reuses its capacity: no allocation once warm
    set_health(health, health_text_);
  }
}

}  // namespace tiller
