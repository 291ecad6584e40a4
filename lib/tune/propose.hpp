// tiller-tune's proposal: from an identified model (identify.hpp), the vehicle file's dynamics
// and the controller and guidance gains, as edits of the three config files that the user
// reviews as a diff. The rule keeps the closed loop the hand tuning made (on the reference
// model, the vehicle file's own dynamics) and moves it to the identified vehicle:
//
//   velocity PID, per axis (surge, sway, yaw):  k_drag = d, k_drag_quad = d2 (the feed-forward
//     is the drag), k_error and ki times m / m_ref (m u' = k_error e + ki int e keeps its poles),
//     i_limit times d / d_ref (what a current costs scales with the drag);
//   station keeping, x and y (the surge model; sway's where identified) and yaw:  kp and ki times
//     m / m_ref, kd = (kd_ref + d_ref) m / m_ref - d (not below 0): m x'' + (d + kd) x' + kp x
//     keeps its poles; i_limit times d / d_ref;
//   guidance: turn_rate times r_max / r_max_ref, r_max the steady yaw rate at the yaw loop's
//     largest torque (velocity_pid.yaw.max_output = d r + d2 r^2): the turn the boat really makes
//     (docs/autonomy.md); turn_drift_rate is kept (docs/tuning.md, "Identifying the model");
//   vehicle file: the identified mass (yaw: plus the file's m23^2 / m22, since a pivot measures
//     m33 - m23^2 / m22), damping and thruster time constant, so what derives from it
//     (braking_decel, the Munk compensation) follows.
// Axes not identified keep their values. Units as in the files (N, m, s, rad).
#pragma once

#include <string>
#include <vector>

#include "sim/dynamics.hpp"
#include "tune/identify.hpp"

namespace tiller::tune {

// What the simulator's model is on each axis of identify()'s per-axis model, for the comparison
// (sim --mass-scale / --damping-scale applied first): surge M11, Xu, Xuu; sway M22, Yv, Yvv;
// heave M33, Zw, Zww, W - B; yaw M66 - M26^2 / M22 (a pivot's inertia: sway follows the yaw
// through the coupling), Nr, Nrr plus the strip-theory cross-flow drag of a pure yaw rotation.
struct AxisTruth {
  double mass = 0, linear = 0, quadratic = 0, bias = 0;
};
std::array<AxisTruth, kAxes> model_axes(const sim::DynamicsParams& d);

struct ConfigFile {
  std::string path;  // as given (shown in the diff)
  std::vector<std::string> before, after;
};

struct Change {
  std::string file, key;
  double from = 0, to = 0;
};

struct Proposal {
  ConfigFile vehicle, control, guidance;
  std::vector<Change> changes;
  double r_max_ref = 0, r_max = 0;  // rad/s
  std::string diff() const;         // unified diff of the three files
};

// `vehicle_file`: the reference model the gains were tuned on; `control_file`,
// `guidance_file`: the hand-tuned gains. Throws config::Error / std::runtime_error naming the
// file and key that is missing.
Proposal propose(const Identified& id, const std::string& vehicle_file,
                 const std::string& control_file, const std::string& guidance_file);

// Writes the proposed files as DIR/config/<kind>/<file> (they reference each other as
// config/..., which resolves inside DIR first) and DIR/tune.diff.
void write_proposal(const Proposal& p, const std::string& dir);

}  // namespace tiller::tune
