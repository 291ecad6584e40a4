// tiller-esc configuration: plain structs and one strict loader (config/esc/*.yaml).
//
// The config names the vehicle file (path relative to the config file); the ESC list must
// cover exactly the vehicle's thrusters, by name, and each ESC's `reversed` flag comes from the
// vehicle file (the one place a thruster is reversed, see docs/escs-and-wiring.md). Keys:
//   vehicle, backend (i2c_tgy | pca9685 | sim | dry_run), rate_hz, command_timeout_ms,
//   disarm_on_timeout, arm_neutral_tolerance, missing_esc (refuse | degraded),
//   write_on_command, min_write_interval_ms, command_senders ([mixer]: the signed senders whose
//   TILLER_THRUSTER_COMMAND is accepted, see docs/safety.md "Who may command"),
//   i2c_tgy: {bus, telemetry, motor_poles}
//   pca9685: {bus, address, pwm_hz, oscillator_hz, oscillator_calibration, external_clock_hz,
//             output (totem_pole | open_drain), min_us, neutral_us, max_us}
//   sim: {unit (throttle_int16 | pulse_us), min_us, neutral_us, max_us}
//   dry_run: {protocol (i2c_tgy | pca9685), print (changes | every_cycle), unplugged: [addr]}
//   escs: [{name, address (i2c_tgy) | channel (pca9685, sim), trim, slew_per_s,
//           min_us, neutral_us, max_us}]
// Every backend section present is checked, whichever backend is chosen.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/time.hpp"
#include "esc/backend.hpp"
#include "esc/pca9685_backend.hpp"
#include "esc/tgy_backend.hpp"
#include "i2c/transport.hpp"

namespace tiller::esc {

enum class MissingEscPolicy { kRefuse, kDegraded };

// The node's safety logic.
struct EscNodeParams {
  double rate_hz = 100;                 // write cycles per second
  TimeUs command_timeout_us = 250'000;  // no thruster command for this long -> neutral
  bool disarm_on_timeout = true;        // and disarm (the pilot must arm again)
  double arm_neutral_tolerance = 0.02;  // |command| <= this counts as neutral for arming
  MissingEscPolicy missing_esc = MissingEscPolicy::kRefuse;
  // Write at once when a changed command arrives (armed), not only on the next cycle: the
  // stick -> ESC latency then does not wait up to one cycle. At most one extra write per
  // min_write_interval_us, so a burst of commands cannot flood the bus.
  bool write_on_command = true;
  TimeUs min_write_interval_us = 2'000;
  // Signed senders (node names) whose thruster commands are accepted; with a signing key the
  // live executor refuses any other (runtime/node.hpp accept_only_from).
  std::vector<std::string> command_senders{"mixer"};
};

struct DryRunParams {
  std::string protocol = "i2c_tgy";  // whose bytes to print: i2c_tgy | pca9685
  bool every_cycle = false;          // false: print a transaction only when its bytes change
  std::vector<int> unplugged;        // addresses whose model is left off the bus (rehearse a fault)
};

struct EscConfig {
  std::string file;          // this config file
  std::string vehicle_file;  // resolved path of the vehicle file
  std::string backend;       // i2c_tgy | pca9685 | sim | dry_run
  EscNodeParams node;
  std::vector<EscChannelParams> escs;
  TgyParams tgy;
  Pca9685Params pca9685;
  bool sim_pulse_us = false;  // sim backend unit: false = int16 throttle, true = pulse us
  DryRunParams dry_run;
};

// Loads the config (and the thruster names and `reversed` flags from its vehicle file).
EscConfig load_esc_config(const config::Value& root);
EscConfig load_esc_config_file(const std::string& path);

// Builds the configured backend. For i2c_tgy and pca9685, `transport` is the bus to use; when
// it is null, /dev/i2c-N from the config is opened (throws with a clear message if it cannot).
// dry_run prints to `dry_run_out` (stdout when null) over a model of the devices.
std::unique_ptr<EscBackend> make_backend(const EscConfig& cfg, i2c::Transport* transport = nullptr,
                                         std::FILE* dry_run_out = nullptr);

}  // namespace tiller::esc
