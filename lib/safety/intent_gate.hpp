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
//   TEST          armed, thruster test: one thruster at the test's command, every other neutral.
//   WAIT_NEUTRAL, INPUT_LOST, or ACTIVE with the pilot in control and its demand neutral or
//                -> TEST          a fresh thruster test request with a new test id naming a
//                thruster
//                                 of the vehicle at |command| <= test_max_command, while neither
//                                 the failsafe is in control nor a failsafe is active (else
//                                 refused: hold says why while that id is held)
//   TEST         -> WAIT_NEUTRAL  the request ends (let go, stale: link loss), another id or
//                                 thruster or command beyond the cap, a pilot demand off
//                                 neutral, an operator START/RESUME, a failsafe becoming active
//                                 or taking control, test_max_duration; the id is used up (a
//                                 new press is needed)
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
enum class GateState : std::int8_t {
  kDisarmed = 0,
  kWaitNeutral = 1,
  kActive = 2,
  kInputLost = 3,
  kTest = 4
};

struct GateParams {
  TimeUs disarm_after_us = 3'000'000;        // armed without good input this long -> disarm
  double neutral_tolerance = 1e-6;           // |demand| per axis counted as centred
  double test_max_command = 0.15;            // thruster test: the largest |command| (normalised)
  TimeUs test_max_duration_us = 10'000'000;  // one press of the test lasts at most this long
};

// A thruster test request (thruster_test_t), as the mixer last received it.
struct TestRequest {
  bool fresh = false;    // received within its freshness limit, valid, active
  std::int64_t id = 0;   // test_id: new for every press
  int thruster = -1;     // index
  double command = 0.0;  // normalised
};

struct GateInput {
  bool armed = false;        // a fresh TILLER_ARM_STATE says armed
  std::int64_t session = 0;  // its session number
  Controller controller = Controller::kNone;
  bool pilot_fresh = false;       // a valid manual demand within its freshness limit
  std::array<double, 6> pilot{};  // that demand (normalised [X Y Z K M N])
  bool source_fresh = false;      // the active source's input is fresh and valid
  TestRequest test;               // a thruster test request
  int n_thrusters = 0;            // the vehicle's thrusters (a test names one of them)
  // A failsafe is active (tiller-failsafe's latest TILLER_VEHICLE_STATUS has an event holding or
  // an action beyond WARN): what it says, e.g. "HOLD: battery 13.1 V < critical 13.2 V", named in
  // the thruster test's refusal. nullptr: none. A thruster test is refused and ended while set.
  const char* failsafe = nullptr;
};

struct GateOutput {
  GateState state = GateState::kDisarmed;
  bool may_move = false;     // thrust may follow the source in control now
  bool arm_allowed = false;  // an arm request may be granted now
  bool disarm = false;       // request a disarm now (once per arming)
  const char* hold = "";     // why thrust is neutral or arming refused ("" when neither)
  int test_thruster = -1;    // TEST: the one thruster to command, at test_command
  double test_command = 0.0;
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
  std::int64_t test_refusals() const { return test_refusals_; }

 private:
  bool is_new_id(std::int64_t id);
  void enter(GateState s) { state_ = s; }
  // The thruster test's part of step(): enter, keep or leave TEST. Returns the hold text.
  const char* step_test(const GateInput& in, bool pilot_neutral, TimeUs now);
  const char* end_test(const char* why);

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
  std::int64_t test_refusals_ = 0;
  char buf_[96] = {};
  // thruster test
  std::int64_t test_id_ = 0;  // the id in TEST, or the last one refused or ended (used up)
  int test_thruster_ = -1;
  double test_command_ = 0.0;
  TimeUs test_start_ = 0;
  std::int64_t gos_ = 0, test_gos_ = 0;  // operator STARTs/RESUMEs seen; at the test's start
  char test_buf_[160] = {};              // why the used-up id is refused, while it is held
};

}  // namespace tiller::safety
