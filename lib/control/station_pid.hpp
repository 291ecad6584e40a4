// The last-meter station-keeping PID of seed 004 (basic_pid_node).
//
// Position error e = target - position (world NED, m) rotated into the body frame FRD:
//   e_x = cos(psi) e_n + sin(psi) e_e,  e_y = -sin(psi) e_n + cos(psi) e_e;
// heading error e_psi = wrap(target - psi) rad. Per axis x, y, yaw:
//   output = kp * e + I - kd * (measured body velocity u, v, r)
// The derivative acts on the measurement (the vehicle's own velocity), so a target that jumps
// gives no derivative kick, and the output is smooth and finite at zero error: no minimum
// force, no division by the distance. The integral is kept as a world-frame force (so it
// stays pointed at a steady current while the vehicle turns), integrates ki * e dt per body
// axis, is bounded per axis by i_limit, and is frozen while the mixer reduced that axis.
// In weathervane mode both components integrate while surge may (the sideways part is made by
// turning, so it must be able to unwind: otherwise a standing offset I_y / kp_y remains after a
// turn), bounded in magnitude by x.i_limit.
//
// Weathervane mode (boats with no sway authority, e.g. the Otter): the demanded world-frame
// force F = R(psi) [x y] is produced by turning the bow along F (or, within reverse_radius, the
// hull's axis: bow or stern) and pushing with surge only; with |F| below weathervane_min_force
// the target heading is held. No hard switches: the heading error blends from the target's to
// the force's with |F| (min_force .. full_force) and from axis to bow with the distance
// (reverse_radius .. + reverse_blend), see station_pid.cpp. The published P + I + D of each
// axis is its output (before the max_output clamp), except sway in weathervane mode: there the
// published sway P, I and D are the sideways part of F, which the heading setpoint turns the bow
// toward, and the sway output is 0. Outputs X, Y in N and N in N m.
#pragma once

#include <array>

#include "control/velocity_pid.hpp"

namespace tiller::control {

struct StationAxisGains {
  double kp = 0;            // N per m (N m per rad)
  double ki = 0;            // N per (m s)
  double kd = 0;            // N per (m/s)
  double i_limit = 0;       // N
  double max_output = 1e5;  // N
};

struct StationPidParams {
  StationAxisGains x, y, yaw;
  double max_dt = 0.5;                 // s: longer gaps do not integrate
  bool weathervane = false;            // no sway authority: point the bow along the force
  double weathervane_min_force = 5;    // N: below this, hold the target heading
  double weathervane_full_force = 10;  // N: above this, follow the force; blended between
  double reverse_radius = 1.0;         // m: within this, push astern rather than turn around
  double reverse_blend = 0.5;          // m: bow rule fades in from reverse_radius over this
  // rad/s, 0 = none: how fast the weathervane may move its heading setpoint (world frame), so
  // that a step of the estimate across the reverse blend swings the bow, not the thrusters.
  double heading_rate_limit = 0;
};

struct StationPidInput {
  double target_n = 0, target_e = 0, target_heading = 0;  // m, m, rad NED
  double n = 0, e = 0, heading = 0;                       // m, m, rad NED
  double u = 0, v = 0, r = 0;                             // body velocity m/s, rad/s
  double dt = 0;                                          // s
  std::array<bool, 3> freeze{false, false, false};        // mixer reduced [X Y N]
};

class StationPid {
 public:
  explicit StationPid(const StationPidParams& p = {}) : p_(p) {}
  PidTerms step(const StationPidInput& in);
  void reset() {
    i_world_ = {0, 0};
    i_yaw_ = 0;
    turn_ = 0;
    have_setpoint_ = false;
  }
  const StationPidParams& params() const { return p_; }

 private:
  // Weathervane: how far the heading follows the force of magnitude fmag (N): 0 below
  // weathervane_min_force, 1 above weathervane_full_force, linear between.
  double force_weight(double fmag) const;
  StationPidParams p_;
  std::array<double, 2> i_world_{0, 0};  // N, north/east
  double i_yaw_ = 0;                     // N m
  int turn_ = 0;  // the weathervane's last turn toward the force: +1 right, -1 left, 0 none yet
  bool have_setpoint_ = false;
  double last_setpoint_ = 0;  // rad NED: the weathervane's last heading setpoint
};

}  // namespace tiller::control
