// tiller-sim's logic: the vehicle simulator as a node. It turns what the ESC bus driver puts on
// the bus (TILLER_ESC_OUTPUT, hardware units) into thrust through each thruster's curve and lag,
// steps the Fossen model (lib/sim/vessel_model.hpp) on its fixed step, and publishes
//   TILLER_ODOMETRY      pose NED + body FRD velocity over ground (with optional seeded noise),
//   TILLER_GROUND_TRUTH  the same without noise,
//   TILLER_SIM_STATE     eta, nu, nu_r, current, thrust per thruster,
//   TILLER_DATUM         with its odometry, once a second: the NED origin's WGS84 point (the
//                        sensors' gnss datum), as tiller-nav publishes its own,
// each at its configured rate (a multiple of the step). With a sensors file (config/sim/
// sensors_*.yaml, `sensors:` or --sensors) it also publishes every simulated sensor from the true
// state on its driver's channel (TILLER_GNSS, _IMU, _HEADING, _PRESSURE, _POWER, _LEAK; NMEA to
// a sink for gpsd: lib/sim/sensor_suite.hpp); with `odometry: estimated` it publishes no
// TILLER_ODOMETRY (tiller-nav makes it from those sensors; ground truth is still published). Runs
// live (tiller-sim) or in lockstep with the other nodes (LockstepExecutor) on simulated time; no
// clock, no file after loading.
//
// ESC output -> thrust: UNIT_THROTTLE_INT16 value / throttle_full_scale, or UNIT_PULSE_US mapped
// by the config's pulse min / neutral / max (1500 + u (max - 1500) for u > 0, 1500 + u (1500 -
// min) otherwise, inverted) gives the motor's command; a thruster with `reversed: true` had its
// sign flipped by tiller-esc, so the simulator flips it back into Tiller's convention and then
// uses Thruster::thrust_from_command (lib/vehicle, the same curve the mixer inverts).
// Disarmed output, or none fresher than esc_timeout (or, with esc_timeout_model: hardware, the
// hold time of the ESC type that sent it), commands zero thrust; the lag then decays the thrust
// as spinning-down propellers would. A message with an unknown thruster name, an
// unknown unit or a value out of range is dropped and counted (the last good one stays, until
// it goes stale).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <tiller/datum_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/sim_state_t.hpp>

#include "core/config.hpp"
#include "core/time.hpp"
#include "runtime/node.hpp"
#include "sim/dynamics.hpp"
#include "sim/environment.hpp"
#include "sim/sensor_suite.hpp"
#include "sim/vessel_model.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller {

struct SimParams {
  std::string vehicle_file;  // resolved path of the vehicle description
  TimeUs step_us = 10'000;   // integration step (and tick period)
  TimeUs odometry_period_us = 50'000;
  TimeUs ground_truth_period_us = 50'000;
  TimeUs sim_state_period_us = 50'000;
  TimeUs esc_timeout_us = 500'000;  // ESC output older than this commands zero thrust
  // How long the last ESC output keeps driving the motors once tiller-esc stops sending:
  //   kSafe      esc_timeout_us for every ESC (the default: a simulated vehicle whose bus driver
  //              died stops, whatever its ESCs would do);
  //   kHardware  as the ESCs would: an I2C throttle ESC (BlueESC/tgy, UNIT_THROTTLE_INT16)
  //              keeps its last throttle for kTgyHoldUs and then stops (docs/escs-and-wiring.md:
  //              about 4-5 s); a PWM ESC behind a PCA9685 (UNIT_PULSE_US) keeps its last pulse, so
  //              the motors keep turning indefinitely (for testing what a dead driver does).
  enum class EscTimeoutModel { kSafe, kHardware };
  EscTimeoutModel esc_timeout_model = EscTimeoutModel::kSafe;
  static constexpr TimeUs kTgyHoldUs = 4'500'000;
  static constexpr TimeUs kForeverUs = 100LL * 365 * 24 * 3600 * kUsPerSecond;
  double pulse_min_us = 1100, pulse_neutral_us = 1500, pulse_max_us = 1900;
  double throttle_full_scale = 32767;
  int max_steps_per_tick = 100;  // live: a late tick catches up at most this many steps
  sim::Vector6 initial_eta = sim::Vector6::Zero();  // [n e d] m, [roll pitch yaw] rad
  sim::Vector6 initial_nu = sim::Vector6::Zero();   // body FRD, m/s, rad/s
  std::uint64_t seed = 1;
  sim::CurrentParams current;
  bool wind_enabled = false;
  // Where wind.enabled was set ("file:line: wind.enabled"), for the error a vehicle without a
  // wind model gives (SimNode refuses wind on an underwater_6dof vehicle).
  std::string wind_enabled_key = "wind.enabled";
  sim::WindParams wind;
  sim::OdometryNoiseParams noise;
  // truth (the default): TILLER_ODOMETRY from the model (plus `noise`); estimated: none (the
  // estimator, tiller-nav, publishes it from the simulated sensors).
  bool publish_odometry = true;
  sim::SensorParams sensors;  // enabled false: no sensor messages
  // A vehicle the controllers were not tuned on (tiller-sim --mass-scale, --damping-scale; for
  // tiller-tune's identification): the vehicle file's mass matrix (and Coriolis mass matrix)
  // times mass_scale, its linear, quadratic and cross-flow damping times damping_scale.
  double mass_scale = 1, damping_scale = 1;
  // A step force (config `disturbance.force_step`, tiller-sim --force-step AT_S:N,E,D): from
  // at_us after the start on, force_ned (N, NED, at the reference point) is held on the
  // vehicle, added to set_disturbance()'s. underwater_6dof only (SimNode refuses it on a surface
  // vessel, naming `force_step_key`).
  struct ForceStep {
    bool enabled = false;
    TimeUs at_us = 0;
    sim::Vector3 force_ned = sim::Vector3::Zero();
  };
  ForceStep force_step;
  std::string force_step_key = "disturbance.force_step";
};

// The vehicle's dynamics with `p`'s mass and damping scales applied (SimNode applies them).
sim::DynamicsParams scaled_dynamics(const sim::DynamicsParams& d, const SimParams& p);

// Reads config/sim/*.yaml strictly. `vehicle:` is resolved relative to the config file's folder
// first, then to the current directory.
SimParams load_sim_params(const config::Value& root);

// A vehicle file read for the simulator: the thrusters (lib/vehicle) and the dynamics (lib/sim),
// with every key of the file checked. With `dynamics.simulator_thrust_curve` every thruster of
// this copy uses that curve (the motors' real one) instead of the file's `curve` (the mixer's).
struct SimVehicle {
  Vehicle vehicle;
  sim::DynamicsParams dynamics;
};
SimVehicle load_sim_vehicle_file(const std::string& path);

class SimNode : public Node {
 public:
  // Throws std::invalid_argument for a non-finite initial state, and config::Error (naming
  // wind.enabled, or the force step's key) when the wind or a force step is given for a vehicle
  // it cannot act on.
  SimNode(const SimParams& params, const SimVehicle& vehicle);
  // Loads the sim config file and the vehicle file it names.
  explicit SimNode(const std::string& config_path);

  void on_tick(TimeUs now) override;
  void on_esc_output(const esc_output_t& m, TimeUs now);

  const sim::VesselModel& model() const { return model_; }
  sim::VesselModel& model() { return model_; }
  const sim::CurrentModel& current() const { return current_; }
  const Vehicle& vehicle() const { return vehicle_; }
  const SimParams& params() const { return p_; }
  // An outside force on the vehicle (N, NED) from the next step on (tests' disturbances;
  // underwater_6dof only). Zero by default.
  void set_disturbance(const sim::Vector3& force_ned) { disturbance_ = force_ned; }
  // Thrust target (N, along each thruster's direction) from the last accepted ESC output.
  double commanded_thrust(int i) const { return commanded_[static_cast<std::size_t>(i)]; }
  bool esc_fresh() const { return esc_was_fresh_; }
  // Maps one ESC value to the motor's normalised command in [-1, 1]; false if out of range.
  bool motor_command(std::int8_t unit, std::int32_t value, double& out) const;
  // The simulated sensors (their battery, their GNSS model); NMEA goes to `sink` (not owned).
  const sim::SensorSuite& sensors() const { return sensors_; }
  void set_nmea_sink(sim::NmeaSink* sink) { sensors_.set_nmea_sink(sink); }

 private:
  void publish_outputs(TimeUs now);
  // The sensors' sample of the state just stepped (nu_before: the velocity before the step).
  void sense(const sim::Vector6& nu_before, double dt);
  void fill_odometry(odometry_t& o, const sim::Vector6& eta, const sim::Vector6& nu, TimeUs now);

  SimParams p_;
  Vehicle vehicle_;
  sim::VesselModel model_;
  sim::CurrentModel current_;
  sim::OdometryNoise noise_;
  sim::SensorSuite sensors_;
  std::array<double, sim::kMaxThrusters> thrust_now_{};
  bool surface_;
  sim::Vector3 disturbance_ = sim::Vector3::Zero();
  Freshness esc_fresh_;
  bool esc_was_fresh_ = false;
  std::int64_t stale_seen_ = 0;
  std::array<double, sim::kMaxThrusters> commanded_{};
  bool started_ = false;
  TimeUs sim_time_ = 0;    // time the model state is at (whole steps)
  TimeUs start_time_ = 0;  // sim_time_ at the first tick
  TimeUs next_odom_ = 0, next_truth_ = 0, next_state_ = 0, next_datum_ = 0;
  odometry_t odom_{}, truth_{};
  sim_state_t state_{};
  std::int64_t* rej_name_;
  std::int64_t* rej_unit_;
  std::int64_t* rej_range_;
  std::int64_t* rej_count_;
  std::int64_t* overruns_;
  std::int64_t* non_finite_;
};

}  // namespace tiller
