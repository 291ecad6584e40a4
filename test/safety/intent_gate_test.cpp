// safety::IntentGate, the safety model's state machine (docs/safety.md), on hand-computed
// sequences: each step's state, may_move, arm_allowed and disarm request.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "safety/intent_gate.hpp"

namespace tiller::safety {
namespace {

constexpr TimeUs kMs = 1000;

GateInput pilot(bool armed, std::int64_t session, bool fresh, double surge) {
  GateInput in;
  in.armed = armed;
  in.session = session;
  in.controller = Controller::kPilot;
  in.pilot_fresh = fresh;
  in.pilot[0] = surge;
  in.source_fresh = fresh;
  return in;
}

GateInput autonomy(bool armed, std::int64_t session, bool fresh) {
  GateInput in;
  in.armed = armed;
  in.session = session;
  in.controller = Controller::kAutonomy;
  in.source_fresh = fresh;
  return in;
}

GateInput failsafe(bool armed, std::int64_t session, bool fresh, double pilot_surge = 0) {
  GateInput in;
  in.armed = armed;
  in.session = session;
  in.controller = Controller::kFailsafe;
  in.pilot_fresh = true;
  in.pilot[0] = pilot_surge;
  in.source_fresh = fresh;
  return in;
}

TEST(IntentGate, AFailsafeTakesOverAMovingVehicleAtOnceAndThePilotCentresAfterIt) {
  IntentGate g;
  g.step(pilot(true, 1, true, 0.0), 0);
  EXPECT_TRUE(g.step(pilot(true, 1, true, -0.8), 10 * kMs).may_move);
  // tiller-failsafe's wrench (a surface) replaces the pilot: active in the same step.
  GateOutput o = g.step(failsafe(true, 1, true, -0.8), 20 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_TRUE(o.may_move);
  // Its input lost: neutral; back: active again.
  o = g.step(failsafe(true, 1, false, -0.8), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kInputLost);
  EXPECT_EQ(std::string(o.hold), "armed: failsafe input lost: neutral");
  EXPECT_TRUE(g.step(failsafe(true, 1, true, -0.8), 40 * kMs).may_move);
  // The failsafe ends with the stick still held: the pilot must centre it first.
  o = g.step(pilot(true, 1, true, -0.8), 50 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  EXPECT_TRUE(g.step(pilot(true, 1, true, 0.0), 60 * kMs).may_move);
}

TEST(IntentGate, AFailsafeNeverStartsAVehicleThatHadNotMovedInThisArming) {
  IntentGate g;
  g.step(pilot(true, 1, true, 0.5), 0);  // armed, the stick never centred: WAIT_NEUTRAL
  GateOutput o = g.step(failsafe(true, 1, true), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  EXPECT_EQ(std::string(o.hold),
            "armed: failsafe in control, neutral (nothing moved in this arming)");
  // Moved, then disarmed and armed again (a new session): the failsafe waits again.
  g.step(pilot(true, 1, true, 0.0), 20 * kMs);
  EXPECT_TRUE(g.step(failsafe(true, 1, true), 30 * kMs).may_move);
  g.step(failsafe(false, 1, true), 40 * kMs);
  EXPECT_FALSE(g.step(failsafe(true, 2, true), 50 * kMs).may_move);
  // Its input fresh, so no disarm for lack of input.
  EXPECT_FALSE(g.step(failsafe(true, 2, true), 4'000 * kMs).disarm);
}

TEST(IntentGate, ArmingIsRefusedWhileThePilotDemandIsNotNeutral) {
  IntentGate g;
  GateOutput o = g.step(pilot(false, 0, true, 1.0), 0);
  EXPECT_EQ(o.state, GateState::kDisarmed);
  EXPECT_FALSE(o.arm_allowed);
  EXPECT_EQ(std::string(o.hold), "pilot demand not neutral (surge +1.00)");
  // No pilot input (joystick absent or not centred): arming allowed, thrust waits (below).
  o = g.step(pilot(false, 0, false, 0.0), 10 * kMs);
  EXPECT_TRUE(o.arm_allowed);
  o = g.step(pilot(true, 1, false, 0.0), 15 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  o = g.step(pilot(false, 1, true, 0.0), 18 * kMs);
  o = g.step(pilot(false, 0, true, 0.0), 20 * kMs);
  EXPECT_TRUE(o.arm_allowed);
  EXPECT_FALSE(o.may_move);
}

TEST(IntentGate, AfterArmingThrustWaitsForACentredStick) {
  IntentGate g;
  g.step(pilot(false, 0, true, 0.0), 0);
  // Armed while neutral, then the stick moves: active at once (neutral shown at arming).
  GateOutput o = g.step(pilot(true, 1, true, 0.0), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_TRUE(o.may_move);
  o = g.step(pilot(true, 1, true, 0.7), 20 * kMs);
  EXPECT_TRUE(o.may_move);
  // A new session (re-armed, the disarmed state missed) with the stick held: wait.
  o = g.step(pilot(true, 2, true, 0.7), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  EXPECT_EQ(std::string(o.hold), "pilot demand not neutral (surge +0.70)");
  o = g.step(pilot(true, 2, true, 0.0), 40 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  o = g.step(pilot(true, 2, true, -0.3), 50 * kMs);
  EXPECT_TRUE(o.may_move);
}

TEST(IntentGate, ARestartedMixerWaitsForNeutralEvenIfArmed) {
  IntentGate g;  // a new process: the first arm state it sees says armed, stick held
  GateOutput o = g.step(pilot(true, 7, true, 1.0), 0);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  o = g.step(pilot(true, 7, true, 0.0), 20 * kMs);
  EXPECT_TRUE(o.may_move);
}

TEST(IntentGate, PilotLinkLossGivesNeutralThenDisarmAndReturnNeedsCentring) {
  GateParams p;
  p.disarm_after_us = 3000 * kMs;
  IntentGate g(p);
  g.step(pilot(true, 1, true, 0.0), 0);
  GateOutput o = g.step(pilot(true, 1, true, 0.5), 100 * kMs);  // last good input at 0.1 s
  EXPECT_TRUE(o.may_move);
  o = g.step(pilot(true, 1, false, 0.0), 700 * kMs);  // stale
  EXPECT_EQ(o.state, GateState::kInputLost);
  EXPECT_FALSE(o.may_move);
  EXPECT_FALSE(o.disarm);
  o = g.step(pilot(true, 1, false, 0.0), 3099 * kMs);
  EXPECT_FALSE(o.disarm);
  o = g.step(pilot(true, 1, false, 0.0), 3100 * kMs);  // 3 s after the last good input
  EXPECT_TRUE(o.disarm);
  EXPECT_EQ(std::string(o.hold), "pilot input lost: disarming");
  EXPECT_EQ(g.disarms(), 1);
  o = g.step(pilot(true, 1, false, 0.0), 3500 * kMs);
  EXPECT_FALSE(o.disarm);  // not every step
  o = g.step(pilot(true, 1, false, 0.0), 4100 * kMs);
  EXPECT_TRUE(o.disarm);  // again a second later: tiller-esc still says armed
  EXPECT_EQ(g.disarms(), 1);
  // Input back with the stick held before the disarm took effect: still neutral.
  o = g.step(pilot(true, 1, true, 0.8), 4200 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  o = g.step(pilot(true, 1, true, 0.0), 4300 * kMs);
  EXPECT_TRUE(o.may_move);
}

TEST(IntentGate, ShortPilotLossReturningCentredResumes) {
  IntentGate g;
  g.step(pilot(true, 1, true, 0.0), 0);
  g.step(pilot(true, 1, false, 0.0), 600 * kMs);
  const GateOutput o = g.step(pilot(true, 1, true, 0.0), 900 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_FALSE(o.disarm);
}

TEST(IntentGate, AutonomyMovesOnlyAfterAnOperatorStartWhileArmed) {
  IntentGate g;
  EXPECT_TRUE(g.step(autonomy(false, 0, true), 0).arm_allowed);  // its thrust waits for START
  EXPECT_TRUE(g.operator_go(42, 5 * kMs));  // START before arming: not carried over
  g.step(autonomy(false, 0, true), 5 * kMs);
  GateOutput o = g.step(autonomy(true, 1, true), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(std::string(o.hold), "armed: waiting for an operator START or RESUME");
  EXPECT_FALSE(g.operator_go(42, 20 * kMs));  // the same id again: ignored
  o = g.step(autonomy(true, 1, true), 20 * kMs);
  EXPECT_FALSE(o.may_move);
  EXPECT_TRUE(g.operator_go(43, 30 * kMs));
  o = g.step(autonomy(true, 1, true), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_TRUE(o.may_move);
  // Input lost: neutral; back: active again without a new START.
  o = g.step(autonomy(true, 1, false), 600 * kMs);
  EXPECT_EQ(o.state, GateState::kInputLost);
  o = g.step(autonomy(true, 1, true), 700 * kMs);
  EXPECT_TRUE(o.may_move);
  // A restart of the mixer (a new gate) while armed: waits for an operator again.
  IntentGate fresh;
  EXPECT_FALSE(fresh.step(autonomy(true, 1, true), 800 * kMs).may_move);
}

TEST(IntentGate, ControllerChangeStartsOver) {
  IntentGate g;
  g.step(pilot(true, 1, true, 0.0), 0);
  EXPECT_TRUE(g.step(pilot(true, 1, true, 0.4), 10 * kMs).may_move);
  // The pilot switches to autonomy: no thrust until an operator go.
  GateOutput o = g.step(autonomy(true, 1, true), 20 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  g.operator_go(9, 30 * kMs);
  EXPECT_TRUE(g.step(autonomy(true, 1, true), 30 * kMs).may_move);
  // Back to the pilot with the stick held: wait for centring.
  o = g.step(pilot(true, 1, true, 0.4), 40 * kMs);
  EXPECT_FALSE(o.may_move);
  EXPECT_TRUE(g.step(pilot(true, 1, true, 0.0), 50 * kMs).may_move);
}

TEST(IntentGate, ReleaseRequestsADisarmAndDisarmingClearsEverything) {
  IntentGate g;
  g.step(autonomy(true, 1, true), 0);
  g.operator_go(1, 0);
  EXPECT_TRUE(g.step(autonomy(true, 1, true), 10 * kMs).may_move);
  g.operator_release(2, 20 * kMs);
  GateOutput o = g.step(autonomy(true, 1, true), 20 * kMs);
  EXPECT_TRUE(o.disarm);
  EXPECT_EQ(std::string(o.hold), "operator release: disarming");
  o = g.step(autonomy(false, 1, true), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kDisarmed);
  EXPECT_FALSE(o.disarm);
  o = g.step(autonomy(true, 2, true), 40 * kMs);
  EXPECT_FALSE(o.disarm);  // the release was for the old arming
  EXPECT_FALSE(o.may_move);
}

TEST(IntentGate, NoInputAtAllAfterArmingDisarmsAfterTheLimit) {
  IntentGate g;
  GateOutput o = g.step(autonomy(true, 1, false), 1000 * kMs);
  EXPECT_FALSE(o.disarm);
  o = g.step(autonomy(true, 1, false), 3999 * kMs);
  EXPECT_FALSE(o.disarm);
  o = g.step(autonomy(true, 1, false), 4000 * kMs);
  EXPECT_TRUE(o.disarm);
  EXPECT_EQ(std::string(o.hold), "autonomy input lost: disarming");
}

// ---- The thruster test (docs/safety.md, "Thruster test"): TEST only while armed with the source
// in control neutral, one thruster at a capped command, left on any other input.

GateInput with_test(GateInput in, std::int64_t id, int thruster, double command) {
  in.test.fresh = true;
  in.test.id = id;
  in.test.thruster = thruster;
  in.test.command = command;
  in.n_thrusters = 4;
  return in;
}

TEST(IntentGateTest, EntersOnlyArmedWithANewPressAndCommandsOneThruster) {
  IntentGate g;
  // A press while disarmed: refused, and used up (arming does not start it).
  GateOutput o = g.step(with_test(pilot(false, 0, false, 0.0), 1, 2, 0.1), 0);
  EXPECT_EQ(o.state, GateState::kDisarmed);
  EXPECT_EQ(std::string(o.hold), "thruster test refused: not armed (arm first)");
  o = g.step(with_test(pilot(true, 1, false, 0.0), 1, 2, 0.1), 20 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold), "thruster test refused: not armed (arm first)");
  // A new press, armed, no pilot input: TEST, thruster 2 at +0.10, the source still held.
  o = g.step(with_test(pilot(true, 1, false, 0.0), 2, 2, 0.1), 40 * kMs);
  EXPECT_EQ(o.state, GateState::kTest);
  EXPECT_FALSE(o.may_move);
  EXPECT_EQ(o.test_thruster, 2);
  EXPECT_DOUBLE_EQ(o.test_command, 0.1);
  EXPECT_EQ(std::string(o.hold), "thruster test: thruster 2 at +0.10");
  // Let go: WAIT_NEUTRAL at once; holding the same id again does not restart it.
  GateInput let_go = pilot(true, 1, false, 0.0);
  let_go.n_thrusters = 4;
  o = g.step(let_go, 60 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold),
            "thruster test ended: the button was let go or the request is stale (press again)");
  o = g.step(with_test(pilot(true, 1, false, 0.0), 2, 2, 0.1), 80 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  o = g.step(with_test(pilot(true, 1, false, 0.0), 3, 0, -0.15), 100 * kMs);
  EXPECT_EQ(o.state, GateState::kTest);
  EXPECT_EQ(o.test_thruster, 0);
  EXPECT_DOUBLE_EQ(o.test_command, -0.15);  // the cap itself is allowed
  EXPECT_EQ(g.test_refusals(), 1);
}

TEST(IntentGateTest, RefusesBeyondTheCapAnUnknownThrusterAMovingSource) {
  IntentGate g;
  g.step(pilot(true, 1, false, 0.0), 0);
  GateOutput o = g.step(with_test(pilot(true, 1, false, 0.0), 1, 1, 0.16), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(std::string(o.hold), "thruster test refused: command beyond thruster_test.max_command");
  o = g.step(with_test(pilot(true, 1, false, 0.0), 2, 1, NAN), 20 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  o = g.step(with_test(pilot(true, 1, false, 0.0), 3, 4, 0.1), 30 * kMs);
  EXPECT_EQ(std::string(o.hold), "thruster test refused: no such thruster");
  o = g.step(with_test(pilot(true, 1, false, 0.0), 4, -1, 0.1), 40 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  // The pilot's stick held off centre (gate waiting for the centre): refused.
  o = g.step(with_test(pilot(true, 1, true, 0.4), 5, 1, 0.1), 50 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(std::string(o.hold), "thruster test refused: the pilot's demand is not neutral");
  EXPECT_EQ(g.test_refusals(), 5);
  // The autonomy flying its mission: refused; before its START: allowed.
  IntentGate a;
  a.step(autonomy(true, 1, true), 0);
  a.operator_go(1, 0);
  EXPECT_TRUE(a.step(autonomy(true, 1, true), 10 * kMs).may_move);
  GateInput ai = with_test(autonomy(true, 1, true), 1, 0, 0.1);
  o = a.step(ai, 20 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold),
            "thruster test refused: the autonomy is in control (abort or release first)");
  IntentGate b;
  b.step(autonomy(true, 1, true), 0);
  o = b.step(with_test(autonomy(true, 1, true), 1, 3, 0.1), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kTest);
  EXPECT_EQ(o.test_thruster, 3);
}

TEST(IntentGateTest, ACentredPilotInControlMayTestAndTakesBackAfterIt) {
  IntentGate g;
  EXPECT_EQ(g.step(pilot(true, 1, true, 0.0), 0).state, GateState::kActive);
  GateOutput o = g.step(with_test(pilot(true, 1, true, 0.0), 1, 1, 0.1), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kTest);
  EXPECT_FALSE(o.may_move);
  // The stick moves during the test: the test ends; the stick must centre again.
  o = g.step(with_test(pilot(true, 1, true, 0.5), 1, 1, 0.1), 20 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_FALSE(o.may_move);
  EXPECT_EQ(std::string(o.hold), "thruster test ended: pilot demand off neutral (press again)");
  o = g.step(pilot(true, 1, true, 0.5), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_FALSE(o.may_move);
  o = g.step(pilot(true, 1, true, 0.0), 40 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
}

TEST(IntentGateTest, LeavesOnEveryOtherInput) {
  const GateInput base = pilot(true, 1, false, 0.0);
  struct Case {
    const char* what;
    GateInput in;
    bool go;
    GateState to;
    const char* hold;
  };
  GateInput other_id = with_test(base, 2, 1, 0.1);
  GateInput other_thruster = with_test(base, 1, 2, 0.1);
  GateInput beyond = with_test(base, 1, 1, -0.2);
  GateInput disarmed = with_test(pilot(false, 1, false, 0.0), 1, 1, 0.1);
  GateInput rearmed = with_test(pilot(true, 2, false, 0.0), 1, 1, 0.1);
  GateInput autonomy_now = with_test(autonomy(true, 1, false), 1, 1, 0.1);
  const Case cases[] = {
      {"another id", other_id, false, GateState::kWaitNeutral,
       "thruster test ended: another test id (press again)"},
      {"another thruster", other_thruster, false, GateState::kWaitNeutral,
       "thruster test ended: another thruster (press again)"},
      {"beyond the cap", beyond, false, GateState::kWaitNeutral,
       "thruster test ended: command beyond thruster_test.max_command (press again)"},
      {"an operator START", with_test(base, 1, 1, 0.1), true, GateState::kWaitNeutral,
       "thruster test ended: an operator START or RESUME (press again)"},
      {"disarmed", disarmed, false, GateState::kDisarmed,
       "thruster test ended: disarmed (press again)"},
      {"a new arming", rearmed, false, GateState::kWaitNeutral,
       "thruster test ended: a new arming (press again)"},
      {"the controller changes", autonomy_now, false, GateState::kWaitNeutral,
       "thruster test ended: the controller changed (press again)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    IntentGate g;
    g.step(base, 0);
    ASSERT_EQ(g.step(with_test(base, 1, 1, 0.1), 10 * kMs).state, GateState::kTest);
    if (c.go) g.operator_go(9, 15 * kMs);
    const GateOutput o = g.step(c.in, 20 * kMs);
    EXPECT_EQ(o.state, c.to);
    EXPECT_EQ(o.test_thruster, -1);
    EXPECT_EQ(std::string(o.hold), c.hold);
  }
}

TEST(IntentGateTest, TimesOutAndHoldingItKeepsTheArmingAlive) {
  GateParams p;
  p.test_max_duration_us = 5'000'000;
  IntentGate g(p);
  const GateInput base = pilot(true, 1, false, 0.0);  // no pilot input at all
  g.step(base, 0);
  ASSERT_EQ(g.step(with_test(base, 1, 0, 0.1), 2000 * kMs).state, GateState::kTest);
  // 4.99 s of test, 6.99 s after arming without pilot input: no disarm while the button is held.
  GateOutput o = g.step(with_test(base, 1, 0, 0.1), 6990 * kMs);
  EXPECT_EQ(o.state, GateState::kTest);
  EXPECT_FALSE(o.disarm);
  o = g.step(with_test(base, 1, 0, 0.1), 7000 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(std::string(o.hold), "thruster test ended: the longest test time (press again)");
  // Without input the disarm follows disarm_after (3 s) after the last held test (6.99 s).
  o = g.step(base, 9980 * kMs);
  EXPECT_FALSE(o.disarm);
  o = g.step(base, 9990 * kMs);
  EXPECT_TRUE(o.disarm);
}

// Safety review: a thruster test could start while tiller-failsafe was in control but waiting
// (WAIT_NEUTRAL: nothing had moved in this arming, or INPUT_LOST), and the refusal while it was
// ACTIVE said "the autonomy is in control". Now any failsafe refuses a test, naming it: the
// failsafe in control in any state, or a failsafe active (GateInput::failsafe) under any
// controller; an active failsafe also ends a running test.
TEST(IntentGateTest, AnyFailsafeRefusesATestAndNamesIt) {
  const std::string in_control =
      "thruster test refused: the failsafe is in control (tiller-failsafe: its wrench or hold in "
      "force; clear it first)";
  // In control, waiting neutral (armed, nothing moved yet): refused, not TEST.
  IntentGate w;
  ASSERT_EQ(w.step(failsafe(true, 1, true), 0).state, GateState::kWaitNeutral);
  GateOutput o = w.step(with_test(failsafe(true, 1, true), 1, 1, 0.1), 10 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold), in_control);
  // In control, its input lost: refused.
  IntentGate l;
  l.step(pilot(true, 1, true, 0.0), 0);
  l.step(failsafe(true, 1, true), 10 * kMs);
  ASSERT_EQ(l.step(failsafe(true, 1, false), 20 * kMs).state, GateState::kInputLost);
  o = l.step(with_test(failsafe(true, 1, false), 1, 1, 0.1), 30 * kMs);
  EXPECT_EQ(o.state, GateState::kInputLost);
  EXPECT_EQ(std::string(o.hold), in_control);
  // In control and moving: the failsafe is named, not the autonomy.
  IntentGate a;
  a.step(pilot(true, 1, true, 0.0), 0);
  ASSERT_EQ(a.step(failsafe(true, 1, true), 10 * kMs).state, GateState::kActive);
  GateInput fi = with_test(failsafe(true, 1, true), 1, 1, 0.1);
  fi.failsafe = "SURFACE: leak";
  o = a.step(fi, 20 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_EQ(std::string(o.hold),
            "thruster test refused: the failsafe is in control (tiller-failsafe: SURFACE: leak; "
            "clear it first)");
  // Active under the pilot (a hold in a manual mode reaches the mixer as the failsafe, but an
  // event can hold while the pilot still flies): refused; cleared, a new press is taken.
  IntentGate p;
  p.step(pilot(true, 1, true, 0.0), 0);
  GateInput pi = with_test(pilot(true, 1, true, 0.0), 1, 1, 0.1);
  pi.failsafe = "WARN: battery 14.2 V < warning 14.4 V";
  o = p.step(pi, 10 * kMs);
  EXPECT_EQ(o.state, GateState::kActive);
  EXPECT_EQ(std::string(o.hold),
            "thruster test refused: a failsafe is active (tiller-failsafe: WARN: battery 14.2 V < "
            "warning 14.4 V; clear it first)");
  EXPECT_EQ(p.step(with_test(pilot(true, 1, true, 0.0), 2, 1, 0.1), 20 * kMs).state,
            GateState::kTest);
  // A failsafe becoming active during a test ends it at once.
  GateInput during = with_test(pilot(true, 1, true, 0.0), 2, 1, 0.1);
  during.failsafe = "HOLD: geofence";
  o = p.step(during, 30 * kMs);
  EXPECT_EQ(o.state, GateState::kWaitNeutral);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold),
            "thruster test ended: a failsafe is active (tiller-failsafe: HOLD: geofence; press "
            "again)");
  // The failsafe taking control during a test: ended, named.
  IntentGate t;
  t.step(pilot(true, 1, true, 0.0), 0);
  ASSERT_EQ(t.step(with_test(pilot(true, 1, true, 0.0), 1, 1, 0.1), 10 * kMs).state,
            GateState::kTest);
  o = t.step(with_test(failsafe(true, 1, true), 1, 1, 0.1), 20 * kMs);
  EXPECT_NE(o.state, GateState::kTest);
  EXPECT_EQ(o.test_thruster, -1);
  EXPECT_EQ(std::string(o.hold),
            "thruster test ended: the failsafe (tiller-failsafe) took control (press again)");
  EXPECT_EQ(w.test_refusals() + l.test_refusals() + a.test_refusals() + p.test_refusals(), 4);
}

}  // namespace
}  // namespace tiller::safety
