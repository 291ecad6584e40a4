// tiller::EscNode: the ESC bus driver's logic (tiller-esc), the one authority on arming.
//
// Inputs: TILLER_THRUSTER_COMMAND (thruster_command_t, normalised [-1, 1] per thruster name,
// + = pushes along the thruster's direction) and TILLER_ARM_REQUEST (arm_request_t).
// Every cycle (rate_hz, default 100 Hz) it computes one normalised motor value per ESC and
// hands it to a backend (esc/backend.hpp) that writes the hardware value (int16 throttle or
// pulse us) on the bus:
//   * disarmed (the start state), or no fresh command for command_timeout (default 250 ms):
//     neutral, and neutral keeps being written so the ESCs stay alive and armed;
//   * armed: command -> motor = (reversed ? -1 : 1) * trim * command, then the optional slew
//     limit (slew_per_s); on a reversal the ramp stops at exactly zero for one cycle before
//     continuing the other way. Disarm, timeout and shutdown go to neutral at once (no ramp).
// Arming (the arm latch of docs/safety.md): an arm request arms only while the commands are
// neutral (|u| <= tolerance for every thruster, or no fresh command) AND the latest fresh command
// says arm_allowed (the mixer's safety gate: the source in control demands neutral; otherwise
// the refusal on TILLER_ARM_STATE gives the mixer's `hold` reason); a disarm request always
// disarms. With disarm_on_timeout the command timeout also disarms. Each granted arming gets a
// new session number (arm_state_t.session).
// Replay and stations (docs/safety.md, "Command authority"): an arm request must carry this
// process's boot nonce (set_boot_nonce; tiller-esc draws a random one at start and announces it
// in arm_state_t.boot_nonce), so one captured before a restart is refused
// (rejected.arm_request.boot_nonce) whatever the clocks say. The request's station is in control
// while armed (arm_state_t.controller); another station's arm is refused with the holder's name
// (rejected.arm_request.station) unless it is a takeover, which hands control over as a new
// session (arm.takeovers; the mixer then waits for the new station's centred stick). Any station
// may disarm.
// A changed command while armed is also written at once (write_on_command, default on; at most
// one extra write per min_write_interval, a command held back going out at the next tick, which
// then comes every min_write_interval), so the stick -> ESC latency does not wait a cycle.
// Outputs: TILLER_ESC_OUTPUT every cycle (what went on the bus, hardware units, and the same
// value mapped back to normalised motor units), TILLER_ARM_STATE on change and at 10 Hz,
// TILLER_ESC_STATUS and TILLER_ESC_TELEMETRY at 10 Hz. shutdown() writes neutral to every ESC.
// A cycle allocates nothing.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/esc_telemetry_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "esc/backend.hpp"
#include "esc/esc_config.hpp"
#include "runtime/node.hpp"

namespace tiller {

class EscNode : public Node {
 public:
  EscNode(esc::EscNodeParams p, std::unique_ptr<esc::EscBackend> backend);
  // Loads a config file and builds its backend (sim; dry_run prints to stdout; i2c_tgy and
  // pca9685 open the configured /dev/i2c-N).
  explicit EscNode(const std::string& config_path);
  // Same, but the hardware backends use `transport` (e.g. the fake bus in tests).
  EscNode(const std::string& config_path, i2c::Transport& transport);
  ~EscNode() override;

  // Initialises the devices and writes neutral. Called by on_tick if nobody did; the app calls
  // it first to refuse to start when an ESC is missing and the config says so.
  esc::StartReport start(TimeUs now);
  // Writes neutral to every ESC and disarms (SIGINT/SIGTERM).
  void shutdown(TimeUs now) override;

  // The nonce arm requests must carry (default 0, what tests and lockstep runs use).
  void set_boot_nonce(std::int64_t nonce) { arm_.boot_nonce = nonce; }
  std::int64_t boot_nonce() const { return arm_.boot_nonce; }
  bool armed() const { return armed_; }
  const std::string& controller() const { return arm_.controller; }
  bool command_fresh() const { return command_fresh_; }
  const esc::EscBackend& backend() const { return *backend_; }
  const esc_output_t& last_output() const { return out_; }
  const esc::EscNodeParams& params() const { return p_; }
  std::int64_t timeouts() const { return timeouts_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  EscNode(const esc::EscConfig& cfg, i2c::Transport* transport);
  void init_messages();
  void on_command(const thruster_command_t& m, TimeUs now);
  void on_arm_request(const arm_request_t& m, TimeUs now);
  bool commands_neutral(TimeUs now, std::size_t* worst);
  void set_armed(bool armed, const std::string& reason, TimeUs now);
  void publish_arm_state(TimeUs now);
  void write_cycle(TimeUs now, bool force_neutral, bool poll_telemetry);
  void write_extra(TimeUs now);  // a command written at once (write_on_command)
  static TimeUs tick_period_for(const esc::EscNodeParams& p);
  void publish_status(TimeUs now);
  void publish_telemetry(TimeUs now);
  void update_health();

  esc::EscNodeParams p_;
  TimeUs cycle_period_;  // the bus cycle, 1 / rate_hz (the tick may be shorter, see .cpp)
  std::unique_ptr<esc::EscBackend> backend_;
  std::size_t n_;
  bool started_ = false;
  esc::StartReport start_report_;

  // Latest accepted command, per ESC index, and its freshness.
  std::vector<double> command_;
  Freshness command_freshness_;
  bool command_fresh_ = false;
  std::vector<std::string> cached_names_;  // names of the last command message
  std::vector<int> cached_map_;            // message index -> ESC index

  bool armed_ = false;
  std::int64_t session_ = 0;
  bool arm_allowed_ = false;   // the latest command's arm_allowed
  std::string hold_;           // and its hold reason
  std::vector<double> motor_;  // current (slewed) normalised motor value per ESC
  std::vector<std::int32_t> hw_;
  TimeUs last_cycle_ = 0;
  bool have_cycle_ = false;
  TimeUs last_extra_write_ = 0;  // the last command-triggered write (write_on_command)
  bool have_extra_write_ = false;
  bool pending_ = false;  // a changed command held back by min_write_interval
  TimeUs next_cycle_ = 0;
  TimeUs next_10hz_ = 0;
  std::int64_t cycles_ = 0;
  std::int64_t timeouts_ = 0;
  std::int64_t last_stale_events_ = 0;
  int health_code_ = -1;

  esc_output_t out_;
  arm_state_t arm_;
  esc_bus_status_t status_;
  esc_telemetry_t telem_;

  std::int64_t* c_nan_;
  std::int64_t* c_range_;
  std::int64_t* c_missing_;
  std::int64_t* c_unknown_;
  std::int64_t* c_source_ = nullptr;  // made on first use
  std::int64_t* c_arm_refused_;
  std::int64_t* c_nonce_;
  std::int64_t* c_station_;
  std::int64_t* c_takeovers_;
  std::int64_t* c_bus_errors_;
};

}  // namespace tiller
