// What a controller does while the estimator says its estimate is not good enough (docs/safety.md,
// "Hold: cancel, abort, pause, stale guidance"): tiller-nav keeps publishing TILLER_ODOMETRY
// through a GNSS outage and flags a part invalid (odometry_t.valid) once its 1-sigma passes
// limits.*; the controller does not take such a message, so its odometry goes stale. Stale
// because the estimator is silent (nothing is known) is input lost: an invalid wrench, so the
// mixer's gate INPUT_LOST, neutral, and its disarm after safety.disarm_after_s. Stale because the
// estimator keeps saying "invalid" is a known state: the controller gives a deliberate neutral, a
// valid zero wrench (the vehicle stays armed, the gate ACTIVE, nothing integrates), and control
// resumes by itself when the odometry is valid again -- for at most `invalid_neutral_s` since it
// went invalid (then the invalid wrench and the mixer's disarm), and only after the odometry was
// valid once (a vehicle that never had a good estimate is refused as before).
//   on_message(invalid, now)  every well-formed, fresh odometry message: whether it lacks a part
//                             this controller needs
//   neutral(now, ...)         true: give the deliberate neutral now
// Pure and allocation-free: times are arguments (µs).
#pragma once

#include "core/time.hpp"

namespace tiller::control {

class EstimateWatch {
 public:
  void on_message(bool invalid, TimeUs now) {
    if (invalid && !invalid_) since_ = now;
    invalid_ = invalid;
    if (invalid) last_ = now;
  }
  // The latest message lacked a needed part.
  bool invalid() const { return invalid_; }
  // `fresh_us`: the controller's odometry_timeout_s (the estimator still talks: its latest
  // invalid message is this recent); `wait_us`: invalid_neutral_s (0: never); `ever_valid`: the
  // controller took a valid message since it started.
  bool neutral(TimeUs now, TimeUs fresh_us, TimeUs wait_us, bool ever_valid) const {
    return invalid_ && ever_valid && wait_us > 0 && now - last_ <= fresh_us &&
           now - since_ <= wait_us;
  }

 private:
  bool invalid_ = false;
  TimeUs since_ = 0;  // the first invalid message of this spell
  TimeUs last_ = 0;   // the latest invalid message
};

}  // namespace tiller::control
