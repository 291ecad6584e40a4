// tiller-mixer's logic: picks the active wrench source, allocates it onto the thrusters and
// publishes one normalised command per thruster (TILLER_THRUSTER_COMMAND) and the allocation
// status (TILLER_ALLOCATION_STATUS) -- at the configured rate, and at once on new input of the
// ACTIVE source and when the active source or the arm state changes (a second wrench feed or a
// joystick that is not in charge does not multiply the command rate).
//
// Inputs: TILLER_MANUAL_DEMAND (normalised stick vector, open loop), TILLER_WRENCH_VELOCITY,
// TILLER_WRENCH_STATION and TILLER_WRENCH_ROV (tiller-rov-control's assisted ROV modes) (wrench,
// N / N m, body FRD), TILLER_ARBITRATION (which source is
// active), TILLER_ARM_STATE (tiller-esc holds the arm latch), TILLER_MISSION_COMMAND (the
// operator's START / RESUME / RELEASE for the autonomy), TILLER_WRENCH_FAILSAFE (tiller-failsafe:
// surface, rise or neutral; while it is fresh and valid it is the source, whatever the
// arbitration says: the pilot's and the autonomy's commands are ignored).
// Safety: a message with NaN/inf or out of range is dropped, counted, and makes that input
// absent at once; an input older than its freshness limit is absent; the active source absent,
// or no fresh "armed" arm state -> every command 0 (armed = false in the message). On top, the
// safety gate (lib/safety/intent_gate.hpp, docs/safety.md) holds thrust neutral until the source
// in control has shown neutral since arming / taking control / its input coming back / this
// process starting, says in every command whether tiller-esc may grant an arm request
// (arm_allowed, hold), and publishes a disarm request on TILLER_ARM_REQUEST when the source in
// control has given no good input for safety.disarm_after_s (default 3 s) or on RELEASE.
// Thruster test (TILLER_THRUSTER_TEST, thruster_test_t, accepted only from thruster_test.senders,
// default [cockpit]): the gate's TEST state (docs/safety.md, "Thruster test") commands the one
// named thruster at the request's command (|command| <= thruster_test.max_command) and every
// other thruster neutral; the request must come again within thruster_test.request_s. A test is
// refused (and a running one ends) while the failsafe is in control or tiller-failsafe's latest
// TILLER_VEHICLE_STATUS has an event holding or an action beyond WARN (no freshness limit, as in
// tiller-velocity-pid: a failsafe that stops reporting does not end its claim; a status older
// than the event limit by its utime is refused).
// Supply voltage: with thrusters whose curve depends on it (`curve: t200`, ThrustCurve's voltage
// tables), each checked TILLER_POWER (power_t) sets the voltage thrust is turned into commands
// at; with none for kSupplyStaleUs (2 s), or none yet, the table's highest voltage (the least
// thrust for a command: the boat gets less thrust than asked, never more), counted in
// supply_voltage.stale. Other vehicles ignore TILLER_POWER.
// Source choice: see select_source() -- the one place that decides.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/thruster_test_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/wrench_t.hpp>

#include "allocation/allocator.hpp"
#include "core/config.hpp"
#include "core/time.hpp"
#include "runtime/node.hpp"
#include "safety/intent_gate.hpp"
#include "safety/station_gate.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller {

struct MixerParams {
  std::string vehicle_file;  // resolved path of the vehicle description
  double rate_hz = 50.0;     // fixed publishing rate
  std::int8_t fallback_source = wrench_t::SOURCE_MANUAL_DEMAND;  // when no fresh arbitration
  TimeUs manual_timeout_us = 500'000;
  TimeUs wrench_timeout_us = 500'000;
  TimeUs arbitration_timeout_us = 1'000'000;
  TimeUs arm_timeout_us = 500'000;
  // safety.disarm_after_s: armed without good input from the source in control this long ->
  // disarm request (docs/safety.md).
  TimeUs disarm_after_us = 3'000'000;
  // `publish_at_once`: active_source (default): new input publishes at once only for the active
  // source, and arm-state / arbitration messages only when they change what the mixer does;
  // every_input: every message publishes at once (the behaviour the golden logs were recorded
  // with).
  bool publish_every_input = false;
  // thruster_test: the gate's TEST state. max_command 0 refuses every test.
  double test_max_command = 0.15;                    // max_command: largest |command|, [0, 0.3]
  TimeUs test_request_us = 500'000;                  // request_s: the request's freshness limit
  TimeUs test_max_duration_us = 10'000'000;          // max_duration_s: one press at most this long
  std::vector<std::string> test_senders{"cockpit"};  // senders: who may ask
};

// Reads config/mixer/<vehicle>.yaml (strict). `vehicle:` is resolved relative to the config
// file's folder first, then to each of its parent folders (so a path from the repository root
// works from any directory), then to the current directory; an absolute path works anywhere.
MixerParams load_mixer_params(const config::Value& root);

// The source the mixer must allocate now: a fresh, valid failsafe wrench (SOURCE_FAILSAFE);
// else seed 004's choose_pid decision, made upstream by lib/control/arbiter and published on
// TILLER_ARBITRATION: the latest fresh arbitration's active_source; with none fresh, the
// configured fallback. SOURCE_NONE means neutral.
std::int8_t select_source(bool arbitration_fresh, std::int8_t arbitration_source,
                          std::int8_t fallback_source, bool failsafe_fresh = false);

class MixerNode : public Node {
 public:
  MixerNode(const MixerParams& params, const Vehicle& vehicle);
  // Loads the mixer config file and the vehicle it names.
  explicit MixerNode(const std::string& config_path);

  void on_tick(TimeUs now) override;
  void shutdown(TimeUs now) override;

  void on_manual(const manual_demand_t& m, TimeUs now);
  void on_wrench_velocity(const wrench_t& m, TimeUs now);
  void on_wrench_station(const wrench_t& m, TimeUs now);
  void on_wrench_rov(const wrench_t& m, TimeUs now);
  void on_wrench_failsafe(const wrench_t& m, TimeUs now);
  void on_arbitration(const arbitration_t& m, TimeUs now);
  void on_arm_state(const arm_state_t& m, TimeUs now);
  void on_mission_command(const mission_command_t& m, TimeUs now);
  void on_thruster_test(const thruster_test_t& m, TimeUs now);
  void on_vehicle_status(const vehicle_status_t& m, TimeUs now);
  void on_power(const power_t& m, TimeUs now);
  static constexpr TimeUs kSupplyStaleUs = 2'000'000;

  const Allocator& allocator() const { return *alloc_; }
  const AllocationResult& last_result() const { return result_; }
  const thruster_command_t& last_command() const { return cmd_; }
  std::int8_t active_source() const { return active_; }
  safety::GateState gate_state() const { return gate_.state(); }
  const MixerParams& params() const { return p_; }

 private:
  struct WrenchInput {
    Freshness fresh;
    Wrench tau = Wrench::Zero();
  };
  void on_wrench(WrenchInput& in, std::int8_t source, const wrench_t& m, TimeUs now);
  std::int8_t source_now(TimeUs now);
  safety::Controller controller_now(TimeUs now);
  void request_disarm(const char* why, TimeUs now);
  void output(TimeUs now);

  MixerParams p_;
  std::unique_ptr<Allocator> alloc_;
  TimeUs power_rx_ = -1;  // the latest TILLER_POWER used (-1: none, or gone stale)
  std::int64_t* supply_stale_ = nullptr;
  Freshness manual_fresh_, arb_fresh_, arm_fresh_;
  Wrench manual_ = Wrench::Zero();
  WrenchInput velocity_, station_, rov_, failsafe_;
  std::int8_t arb_source_ = wrench_t::SOURCE_NONE;
  std::int8_t arb_mode_ = 0;
  bool armed_ = false;
  std::int64_t session_ = 0;
  Freshness test_fresh_;
  safety::TestRequest test_;  // the latest accepted request (fresh: active)
  // tiller-failsafe's latest status, when a failsafe is active: "<ACTION>: <reason>" ("": none).
  char failsafe_text_[128] = {};
  safety::IntentGate gate_;
  // The heartbeat's status text, kept here so that a changed text (the gate's refusal with the
  // stick's value) is compared by content and handed over without a temporary string.
  std::string health_text_;
  std::int8_t active_ = wrench_t::SOURCE_NONE;
  AllocationResult result_;
  thruster_command_t cmd_{};
  allocation_status_t status_{};
  std::int64_t* rej_manual_;
  std::int64_t* rej_station_;  // a manual demand from a station not in control
  safety::StationGate stations_;
  std::int64_t* rej_wrench_;
  std::int64_t* rej_arb_;
  std::int64_t* rej_mission_;
  std::int64_t* held_neutral_;
  std::int64_t* disarm_requests_;
  std::int64_t* rej_arb_mode_ = nullptr;  // made on first use
  std::int64_t* neutral_disarmed_;
  std::int64_t* neutral_no_input_;
  std::int64_t* rej_test_;
  std::int64_t* test_started_;
  std::int64_t* test_refused_;
  std::int64_t stale_seen_ = 0;
  std::int8_t health_ = -1;
};

}  // namespace tiller
