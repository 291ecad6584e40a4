// ESC backends: what turns one normalised motor value per ESC into bytes on a bus.
//
// The ESC node (esc/esc_node.hpp) does the safety logic (arming, timeout, reverse, trim, slew)
// in normalised motor units u in [-1, 1] (+ = the motor's own forward, after the vehicle file's
// `reversed` flag). A backend maps u to its hardware value (int16 throttle for the BlueESC/tgy
// I2C protocol, pulse width in us for PWM ESCs on a PCA9685) and writes one value per ESC per
// cycle. Each ESC is independent: a failed transaction is counted for that ESC (EscStats) and
// retried on the next cycle; the other ESCs still get their writes. Hardware units exist only
// here and in the simulator's thruster model.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace tiller::esc {

// Pulse widths of a PWM ESC, us. u > 0: neutral + u (max - neutral); u <= 0: neutral + u
// (neutral - min) (docs/escs-and-wiring.md).
struct PulseRange {
  double min_us = 1100;
  double neutral_us = 1500;
  double max_us = 1900;
};

// One ESC as the config describes it.
struct EscChannelParams {
  std::string name;       // thruster name, as in the vehicle file
  int address = 0;        // I2C address (i2c_tgy), board channel 0..15 (pca9685), index (sim)
  bool reversed = false;  // from the vehicle file: positive motor value pushes against `direction`
  double trim = 1.0;      // output scale in (0, 1]: turns a strong thruster down to match others
  double slew_per_s = 0;  // max change of the normalised output per second; 0 = no limit
  PulseRange pulse;       // pca9685 (and sim with unit pulse_us) only
};

// Bus health of one ESC since start.
struct EscStats {
  bool present = false;                 // answered at start or since
  std::int64_t write_errors = 0;        // failed throttle/pulse writes
  std::int64_t read_errors = 0;         // failed telemetry reads
  std::int64_t consecutive_errors = 0;  // failed transactions since the last good one
  int last_errno = 0;                   // errno of the last failure (0 = none yet)
};

// Last telemetry sample of one ESC (tgy only; zeros and sample_utime 0 elsewhere).
struct EscTelemetry {
  TimeUs sample_utime = 0;  // us, 0 = never read
  double rpm = 0;           // rev/min, signed as the last command
  double voltage = 0;       // V
  double current = 0;       // A
  double temperature = 0;   // degC
  bool alive = false;       // identifier byte 0xAB seen on the last read
};

// What start() found.
struct StartReport {
  bool all_present = true;
  std::string message;  // one line per missing device; empty when all answered
};

class EscBackend {
 public:
  explicit EscBackend(std::vector<EscChannelParams> escs);
  virtual ~EscBackend() = default;
  EscBackend(const EscBackend&) = delete;
  EscBackend& operator=(const EscBackend&) = delete;

  // "i2c_tgy", "pca9685", "sim" (or "dry_run" when set_label says so): esc_output_t.backend.
  const std::string& label() const { return label_; }
  void set_label(std::string l) { label_ = std::move(l); }
  virtual std::int8_t unit() const = 0;  // esc_output_t::UNIT_*
  virtual std::string bus() const = 0;   // e.g. "/dev/i2c-1", "sim"
  virtual bool has_telemetry() const { return false; }

  std::size_t size() const { return escs_.size(); }
  const EscChannelParams& channel(std::size_t i) const { return escs_[i]; }

  // Start-up: initialise the devices, write neutral to each ESC and find out which answer.
  virtual StartReport start(TimeUs now) = 0;
  // Normalised motor value in [-1, 1] -> hardware value, and back (exact for neutral).
  virtual std::int32_t to_hardware(std::size_t i, double u) const = 0;
  virtual double to_normalized(std::size_t i, std::int32_t hw) const = 0;
  // Writes hw[i] to every ESC i (size() values). Never throws, never allocates.
  virtual void write(const std::int32_t* hw, TimeUs now) = 0;
  // Reads telemetry from at most one ESC (round robin). True if a new sample was stored.
  virtual bool poll_telemetry(TimeUs now) {
    (void)now;
    return false;
  }

  const EscStats& stats(std::size_t i) const { return stats_[i]; }
  const EscTelemetry& telemetry(std::size_t i) const { return telemetry_[i]; }
  // Keeps an object (the transport the backend talks through) alive as long as the backend.
  void keep(std::shared_ptr<void> p) { kept_.push_back(std::move(p)); }

 protected:
  // Records the result of one transaction for ESC i (err 0 = success).
  void record(std::size_t i, int err, bool is_write);

  std::string label_;
  std::vector<EscChannelParams> escs_;
  std::vector<EscStats> stats_;
  std::vector<EscTelemetry> telemetry_;

 private:
  std::vector<std::shared_ptr<void>> kept_;
};

// Hardware conversions shared by the backends and the simulator's view of esc_output_t.
// int16 throttle: round(u * 32767), clamped to [-32767, 32767]; back: hw / 32767.
std::int32_t throttle_from_normalized(double u);
double normalized_from_throttle(std::int32_t throttle);
// Pulse width, rounded to whole us; back: exact inverse of the piecewise-linear map.
std::int32_t pulse_from_normalized(double u, const PulseRange& r);
double normalized_from_pulse(std::int32_t pulse_us, const PulseRange& r);

}  // namespace tiller::esc
