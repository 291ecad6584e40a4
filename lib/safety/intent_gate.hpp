// safety::IntentGate: the one state machine that decides whether thrust may leave neutral
// (docs/safety.md, "Safety model"). tiller-mixer hosts it, because the mixer sees every command
// source and knows which one is in control; tiller-esc holds the arm latch and grants an arm
// request only while the mixer's latest command says `arm_allowed` (thruster_command_t).
//
// The source in control belongs to a controller: the PILOT (modes MANUAL_OPEN_LOOP,
// MANUAL_CLOSED_LOOP and the ROV modes STABILISE .. POSITION_HOLD: the stick, through
// TILLER_MANUAL_DEMAND), the AUTONOMY (WAYPOINTING: path follower, velocity PID, station
// keeping), the FAILSAFE (tiller-failsafe's surface, rise or neutral wrench, or its hold through
// station keeping in a manual or ROV mode), or NONE.
//
// States (thruster_command_t GATE_*) and transitions, evaluated by step() at every output:
//   DISARMED      no fresh "armed" TILLER_ARM_STATE. Start state (a restarted mixer starts here).
//   WAIT_NEUTRAL  armed, but the source in control has not shown its start condition since the
//                 latest of: this arming (a new arm_state_t session), the controller changing,
//                 its input coming back (pilot), this process starting. Thrust neutral.
//   ACTIVE        thrust follows the source in control.
//   INPUT_LOST    armed, the source's input is missing: neutral.
//
//   any          -> DISARMED      the arm state is not a fresh "armed"
//   DISARMED     -> WAIT_NEUTRAL  armed
//   any armed    -> WAIT_NEUTRAL  a new arm session, or the controller changes
//   WAIT_NEUTRAL -> ACTIVE        pilot: a fresh, valid, all-zero manual demand;
//                                 autonomy: an operator START or RESUME (mission_command_t, a new
//                                 id) received while armed (kept for this arming until used, or
//                                 until the pilot takes control);
//                                 failsafe: its input fresh, and the gate was ACTIVE earlier in
//                                 this arming (a failsafe never starts a vehicle that had not
//                                 moved; leaving it, the pilot or autonomy starts over from
//                                 WAIT_NEUTRAL)
//   ACTIVE       -> INPUT_LOST    the source's input is stale or invalid (pilot: the manual demand
//                                 or, in closed loop, the velocity PID's wrench; autonomy: the
//                                 active wrench, or no wrench source at all)
//   INPUT_LOST   -> WAIT_NEUTRAL  pilot input back (the stick must be centred again)
//   INPUT_LOST   -> ACTIVE        autonomy or failsafe input back
// Disarm: armed with no good input from the source in control for `disarm_after` (default 3 s,
// counted from the later of the last good input and the arming), or an operator RELEASE: step()
// returns disarm = true (once, then every second while still armed), and the mixer publishes
// a disarm request.
// arm_allowed: false only while the pilot is in control and the pilot's fresh, valid manual demand
// is not all zero (hold names the axis). With no pilot input arming is allowed: thrust then waits
// in WAIT_NEUTRAL for a centred stick. Always for the autonomy (its thrust waits for the
// operator's START) and for NONE.
// No clock, no allocation: times are arguments, reasons are static or in a fixed buffer.
#pragma once

#include <array>
#include <cstdint>

#include "core/time.hpp"

namespace tiller::safety {

enum class Controller : std::int8_t { kNone, kPilot, kAutonomy, kFailsafe };
// Values equal thruster_command_t GATE_* (checked in intent_gate.cpp).
enum class GateState : std::int8_t { kDisarmed = 0, kWaitNeutral = 1, kActive = 2, kInputLost = 3 };

struct GateParams {
  TimeUs disarm_after_us = 3'000'000;  // armed without good input this long -> disarm
  double neutral_tolerance = 1e-6;     // |demand| per axis counted as centred
};

struct GateInput {
  bool armed = false;        // a fresh TILLER_ARM_STATE says armed
  std::int64_t session = 0;  // its session number
  Controller controller = Controller::kNone;
  bool pilot_fresh = false;       // a valid manual demand within its freshness limit
  std::array<double, 6> pilot{};  // that demand (normalised [X Y Z K M N])
  bool source_fresh = false;      // the active source's input is fresh and valid
};

struct GateOutput {
  GateState state = GateState::kDisarmed;
  bool may_move = false;     // thrust may follow the source in control now
  bool arm_allowed = false;  // an arm request may be granted now
  bool disarm = false;       // request a disarm now (once per arming)
  const char* hold = "";     // why thrust is neutral or arming refused ("" when neither)
};

class IntentGate {
 public:
  explicit IntentGate(const GateParams& p = {}) : p_(p) {}

  // An operator START or RESUME (mission_command_t) at `now`; a repeated id is ignored.
  // Returns true when it was new.
  bool operator_go(std::int64_t command_id, TimeUs now);
  // An operator RELEASE: the next step() requests a disarm. Returns true when it was new.
  bool operator_release(std::int64_t command_id, TimeUs now);
  GateOutput step(const GateInput& in, TimeUs now);

  GateState state() const { return state_; }
  const GateParams& params() const { return p_; }
  // Counters for the heartbeat.
  std::int64_t disarms() const { return disarms_; }

 private:
  bool is_new_id(std::int64_t id);
  void enter(GateState s) { state_ = s; }

  GateParams p_;
  GateState state_ = GateState::kDisarmed;
  Controller controller_ = Controller::kNone;
  std::int64_t session_ = -1;
  bool go_pending_ = false;  // START/RESUME seen, not yet consumed by WAIT_NEUTRAL
  bool release_pending_ = false;
  bool disarm_sent_ = false;  // this arming
  bool moved_ = false;        // ACTIVE at some time in this arming
  TimeUs disarm_sent_at_ = 0;
  TimeUs last_good_ = 0;  // last step with good input from the source (or the arming)
  std::array<std::int64_t, 8> seen_ids_{};  // the last ids acted on
  std::size_t next_id_slot_ = 0;
  std::int64_t disarms_ = 0;
  char buf_[96] = {};
};

}  // namespace tiller::safety
