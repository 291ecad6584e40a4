#include "safety/intent_gate.hpp"

#include <cmath>
#include <cstdio>

#include <tiller/thruster_command_t.hpp>

namespace tiller::safety {

static_assert(static_cast<int>(GateState::kDisarmed) == thruster_command_t::GATE_DISARMED);
static_assert(static_cast<int>(GateState::kWaitNeutral) == thruster_command_t::GATE_WAIT_NEUTRAL);
static_assert(static_cast<int>(GateState::kActive) == thruster_command_t::GATE_ACTIVE);
static_assert(static_cast<int>(GateState::kInputLost) == thruster_command_t::GATE_INPUT_LOST);
static_assert(static_cast<int>(GateState::kTest) == thruster_command_t::GATE_TEST);

namespace {
constexpr const char* kAxisNames[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
}

bool IntentGate::is_new_id(std::int64_t id) {
  for (const std::int64_t s : seen_ids_)
    if (s == id && id != 0) return false;
  seen_ids_[next_id_slot_] = id;
  next_id_slot_ = (next_id_slot_ + 1) % seen_ids_.size();
  return true;
}

bool IntentGate::operator_go(std::int64_t command_id, TimeUs) {
  if (!is_new_id(command_id)) return false;
  go_pending_ = true;
  ++gos_;
  return true;
}

bool IntentGate::operator_release(std::int64_t command_id, TimeUs) {
  if (!is_new_id(command_id)) return false;
  release_pending_ = true;
  return true;
}

GateOutput IntentGate::step(const GateInput& in, TimeUs now) {
  GateOutput out;
  // Whether the pilot's demand is centred (and, if not, the first axis that is not).
  int off_axis = -1;
  if (in.pilot_fresh) {
    for (int i = 0; i < 6 && off_axis < 0; ++i)
      if (!(std::fabs(in.pilot[static_cast<std::size_t>(i)]) <= p_.neutral_tolerance)) off_axis = i;
  }
  const bool pilot_neutral = in.pilot_fresh && off_axis < 0;

  // arm_allowed and its reason, whatever the state.
  const char* refuse = "";
  if (in.controller == Controller::kPilot) {
    if (off_axis >= 0) {
      std::snprintf(buf_, sizeof buf_, "pilot demand not neutral (%s %+.2f)", kAxisNames[off_axis],
                    in.pilot[static_cast<std::size_t>(off_axis)]);
      refuse = buf_;
    }
  }
  out.arm_allowed = refuse[0] == '\0';

  if (!in.armed) {
    if (state_ == GateState::kTest) end_test("disarmed");
    enter(GateState::kDisarmed);
    go_pending_ = false;
    release_pending_ = false;
    disarm_sent_ = false;
    moved_ = false;
    session_ = -1;
    out.state = state_;
    out.hold = refuse;
    if (in.test.fresh && in.test.id != test_id_) {  // a press while disarmed is used up
      test_id_ = in.test.id;
      ++test_refusals_;
      std::snprintf(test_buf_, sizeof test_buf_, "thruster test refused: not armed (arm first)");
    }
    if (in.test.fresh && in.test.id == test_id_ && refuse[0] == '\0') out.hold = test_buf_;
    return out;
  }
  // Armed. A new arming, or another controller, starts over from WAIT_NEUTRAL.
  if (state_ == GateState::kDisarmed || in.session != session_ || in.controller != controller_) {
    if (state_ == GateState::kDisarmed || in.session != session_) {
      disarm_sent_ = false;
      moved_ = false;
      last_good_ = now;
    }
    if (state_ == GateState::kTest)
      end_test(in.session != session_ ? "a new arming"
               : in.controller == Controller::kFailsafe
                   ? "the failsafe (tiller-failsafe) took control"
                   : "the controller changed");
    session_ = in.session;
    controller_ = in.controller;
    enter(GateState::kWaitNeutral);
  }

  const bool pilot = controller_ == Controller::kPilot;
  const bool autonomy = controller_ == Controller::kAutonomy;
  const bool failsafe = controller_ == Controller::kFailsafe;
  const bool input_ok =
      pilot ? in.pilot_fresh && in.source_fresh : (autonomy || failsafe) && in.source_fresh;
  if (input_ok) last_good_ = now;

  switch (state_) {
    case GateState::kWaitNeutral:
      if (pilot && pilot_neutral && in.source_fresh) {
        enter(GateState::kActive);
        go_pending_ = false;  // the pilot took control: a later switch to autonomy needs a new go
      } else if (autonomy && go_pending_) {
        enter(input_ok ? GateState::kActive : GateState::kInputLost);
        go_pending_ = false;
      } else if (failsafe && moved_ && input_ok) {
        enter(GateState::kActive);
      }
      break;
    case GateState::kActive:
      if (!input_ok) enter(GateState::kInputLost);
      break;
    case GateState::kInputLost:
      if (input_ok)
        enter(pilot ? (pilot_neutral ? GateState::kActive : GateState::kWaitNeutral)
                    : GateState::kActive);
      break;
    case GateState::kDisarmed:
    case GateState::kTest:  // step_test() decides
      break;
  }
  const char* test_hold = step_test(in, pilot_neutral, now);

  out.state = state_;
  out.may_move = state_ == GateState::kActive;
  if (state_ == GateState::kActive) moved_ = true;
  if (state_ == GateState::kWaitNeutral) {
    out.hold = pilot      ? (in.pilot_fresh ? "armed: waiting for the stick to be centred"
                                            : "armed: waiting for pilot input (stick centred)")
               : autonomy ? "armed: waiting for an operator START or RESUME"
               : failsafe ? "armed: failsafe in control, neutral (nothing moved in this arming)"
                          : "armed: no source in control";
  } else if (state_ == GateState::kInputLost) {
    out.hold = pilot      ? "armed: pilot input lost: neutral"
               : failsafe ? "armed: failsafe input lost: neutral"
                          : "armed: autonomy input lost: neutral";
  }
  if (!out.may_move && refuse[0] != '\0' && state_ != GateState::kInputLost) out.hold = refuse;
  if (test_hold != nullptr) out.hold = test_hold;
  if (state_ == GateState::kTest) {
    out.test_thruster = test_thruster_;
    out.test_command = test_command_;
  }

  const bool timed_out = !input_ok && now - last_good_ >= p_.disarm_after_us;
  // Once, then again every second while tiller-esc still says armed (a lost request).
  if ((timed_out || release_pending_) && (!disarm_sent_ || now - disarm_sent_at_ >= kUsPerSecond)) {
    if (!disarm_sent_) ++disarms_;
    disarm_sent_ = true;
    disarm_sent_at_ = now;
    out.disarm = true;
    out.hold = release_pending_ ? "operator release: disarming"
               : pilot          ? "pilot input lost: disarming"
               : failsafe       ? "failsafe input lost: disarming"
                                : "autonomy input lost: disarming";
  }
  return out;
}

const char* IntentGate::end_test(const char* why) {
  enter(GateState::kWaitNeutral);
  std::snprintf(test_buf_, sizeof test_buf_, "thruster test ended: %s (press again)", why);
  return test_buf_;
}

const char* IntentGate::step_test(const GateInput& in, bool pilot_neutral, TimeUs now) {
  const TestRequest& t = in.test;
  const bool cmd_ok = std::fabs(t.command) <= p_.test_max_command;  // false for NaN
  if (state_ == GateState::kTest) {
    if (in.failsafe != nullptr) {
      enter(GateState::kWaitNeutral);
      std::snprintf(test_buf_, sizeof test_buf_,
                    "thruster test ended: a failsafe is active (tiller-failsafe: %s; press again)",
                    in.failsafe);
      return test_buf_;
    }
    const char* why = !t.fresh           ? "the button was let go or the request is stale"
                      : t.id != test_id_ ? "another test id"
                      : t.thruster != test_thruster_ ? "another thruster"
                      : !cmd_ok                      ? "command beyond thruster_test.max_command"
                      : in.pilot_fresh && !pilot_neutral             ? "pilot demand off neutral"
                      : gos_ != test_gos_                            ? "an operator START or RESUME"
                      : now - test_start_ >= p_.test_max_duration_us ? "the longest test time"
                                                                     : nullptr;
    if (why != nullptr) return end_test(why);
    test_command_ = t.command;
    last_good_ = now;  // an operator holds the button: no disarm for want of input
    std::snprintf(test_buf_, sizeof test_buf_, "thruster test: thruster %d at %+.2f",
                  test_thruster_, test_command_);
    return test_buf_;
  }
  if (!t.fresh) return nullptr;
  if (t.id == test_id_) return test_buf_[0] != '\0' ? test_buf_ : nullptr;  // used up
  test_id_ = t.id;  // a new press: taken now or refused, never retried
  const bool pilot_ok = !in.pilot_fresh || pilot_neutral;
  // Any failsafe first, whatever the gate's state: the failsafe in control (its wrench, or its
  // hold in a manual mode), even while it waits neutral; or one active under another controller.
  if (controller_ == Controller::kFailsafe || in.failsafe != nullptr) {
    ++test_refusals_;
    std::snprintf(test_buf_, sizeof test_buf_,
                  "thruster test refused: %s (tiller-failsafe: %s; clear it first)",
                  controller_ == Controller::kFailsafe ? "the failsafe is in control"
                                                       : "a failsafe is active",
                  in.failsafe != nullptr ? in.failsafe : "its wrench or hold in force");
    return test_buf_;
  }
  const char* why = state_ == GateState::kActive && controller_ == Controller::kAutonomy
                        ? "the autonomy is in control (abort or release first)"
                    : !pilot_ok ? "the pilot's demand is not neutral"
                    : t.thruster < 0 || t.thruster >= in.n_thrusters ? "no such thruster"
                    : !cmd_ok ? "command beyond thruster_test.max_command"
                              : nullptr;
  if (why != nullptr) {
    ++test_refusals_;
    std::snprintf(test_buf_, sizeof test_buf_, "thruster test refused: %s", why);
    return test_buf_;
  }
  enter(GateState::kTest);
  test_gos_ = gos_;
  test_thruster_ = t.thruster;
  test_command_ = t.command;
  test_start_ = now;
  last_good_ = now;
  std::snprintf(test_buf_, sizeof test_buf_, "thruster test: thruster %d at %+.2f", test_thruster_,
                test_command_);
  return test_buf_;
}

}  // namespace tiller::safety
