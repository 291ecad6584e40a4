// Rig for the ROV pilot modes in closed loop, one process on simulated time: the joystick rig
// of flight.hpp (TeleopNode with an Extreme 3D Pro preset -> MixerNode -> EscNode sim backend)
// plus tiller-rov-control's RovControlNode and the 6-DOF SimNode, the programs and configs of
// config/launch/sim_rov6_joystick.yaml. The water: a constant current (0.3 m/s toward 30 deg by
// default), the vehicle made slightly positively buoyant (buoyancy = weight + extra_buoyancy_n),
// starting at rest at `depth_m`. With dvl_nav the odometry is tiller-nav's, on the simulated
// sensors with the DVL (the ROV's real estimate), instead of the simulator's noisy truth. It
// records every thruster command, to find the largest step of any thruster between two consecutive
// commands (no thrust step on a switch).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tiller/controller_mode_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "control/rov_node.hpp"
#include "core/angles.hpp"
#include "flight.hpp"
#include "nav/nav_node.hpp"
#include "sim/sim_node.hpp"

namespace tiller::e2e {

struct RovSetup {
  std::string teleop = "extreme3dpro_seed001.yaml";
  std::string mixer = "config/mixer/seed001_rov6.yaml";
  std::string esc = "config/esc/seed001_sim.yaml";
  std::string vehicle = "config/vehicles/seed001_rov6.yaml";
  std::string control = "config/control/seed001_rov6.yaml";
  double current_m_s = 0.3;
  double current_toward_deg = 30;
  double extra_buoyancy_n = 2.0;  // N up beyond the weight (slightly positive)
  double depth_m = 2.0;
  double blend_s = -1;         // >= 0: instead of the control file's
  bool trust_position = true;  // the simulator's odometry has no covariance; its position is exact
  // Odometry noise (1 sigma): a Bar30-like depth, an IMU's attitude and rates, a DVL's velocity.
  double position_std_m = 0.003;
  double orientation_std_deg = 0.1;
  double velocity_std_m_s = 0.005;
  double rate_std_deg_s = 0.2;
  // The odometry from tiller-nav (config/nav/rov_dvl.yaml) on the simulated sensors
  // (config/sim/sensors/rov.yaml: IMU, heading, pressure, DVL) instead of the simulator's noisy
  // truth: the position is the DVL's dead reckoning, with its covariance (trust_position off).
  bool dvl_nav = false;
  std::vector<sim::DvlOutage> dvl_outages;  // with dvl_nav: no DVL report at all in these
};

// The shipped config files of a simulated ROV by name: "seed001_rov6" (RovSetup's defaults),
// "bluerov2" or "seed000_rov4"; the rest of RovSetup at its defaults.
inline RovSetup rov_setup(const std::string& vehicle) {
  RovSetup s;
  if (vehicle == "seed001_rov6") return s;
  if (vehicle == "bluerov2") {
    s.teleop = "extreme3dpro_bluerov2.yaml";
    s.esc = "config/esc/bluerov2_sim.yaml";
  } else if (vehicle == "seed000_rov4") {
    s.teleop = "extreme3dpro_seed000.yaml";
    s.esc = "config/esc/seed000_sim.yaml";
  } else {
    throw std::invalid_argument("rov_setup: no simulated ROV named " + vehicle);
  }
  s.mixer = "config/mixer/" + vehicle + ".yaml";
  s.vehicle = "config/vehicles/" + vehicle + ".yaml";
  s.control = "config/control/" + vehicle + ".yaml";
  return s;
}

inline SimParams rov_sim_params(const RovSetup& s) {
  const auto root = config::Value::load_file(kSrc + "/config/sim/sim.yaml");
  SimParams p = load_sim_params(root);
  root.check_all_used();
  p.vehicle_file = kSrc + "/" + s.vehicle;
  p.current.model =
      s.current_m_s > 0 ? sim::CurrentParams::Model::kConstant : sim::CurrentParams::Model::kNone;
  p.current.speed_m_s = s.current_m_s;
  p.current.toward_rad = deg_to_rad(s.current_toward_deg);
  p.initial_eta[2] = s.depth_m;
  p.noise.position_std_m = s.position_std_m;
  p.noise.orientation_std_rad = deg_to_rad(s.orientation_std_deg);
  p.noise.linear_velocity_std_m_s = s.velocity_std_m_s;
  p.noise.angular_velocity_std_rad_s = deg_to_rad(s.rate_std_deg_s);
  if (s.dvl_nav) {
    p.noise = {};
    p.publish_odometry = false;
    p.sensors = sim::load_sensor_file(kSrc + "/config/sim/sensors/rov.yaml", p.step_us);
    p.sensors.dvl_outages = s.dvl_outages;
  }
  return p;
}

inline SimVehicle rov_sim_vehicle(const RovSetup& s) {
  SimVehicle v = load_sim_vehicle_file(kSrc + "/" + s.vehicle);
  v.dynamics.buoyancy_n = v.dynamics.weight_n + s.extra_buoyancy_n;
  return v;
}

inline control::RovControlParams rov_params(const RovSetup& s) {
  control::RovControlParams p = control::load_rov_control_file(kSrc + "/" + s.control);
  if (s.trust_position && !s.dvl_nav) p.require_position_covariance = false;
  if (s.blend_s >= 0) p.blend_s = s.blend_s;
  return p;
}

struct RovRig {
  explicit RovRig(const RovSetup& s = {})
      : f(s.teleop, s.mixer, s.esc),
        sim(rov_sim_params(s), rov_sim_vehicle(s)),
        rov(rov_params(s)) {
    f.ex.add(rov);
    f.ex.add(sim);
    if (s.dvl_nav) {
      nav = std::make_unique<nav::NavNode>(nav::load_nav_file(kSrc + "/config/nav/rov_dvl.yaml"));
      f.ex.add(*nav);
    }
    f.ex.observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      if (ch != channels::kThrusterCommand) return;
      thruster_command_t c;
      c.decode(d, 0, n);
      if (!last.command.empty() && c.n_thrusters == last.n_thrusters) {
        double step = 0;
        for (int i = 0; i < c.n_thrusters; ++i)
          step = std::max(step, std::fabs(c.command[static_cast<std::size_t>(i)] -
                                          last.command[static_cast<std::size_t>(i)]));
        if (step > max_step) {
          max_step = step;
          max_step_at = t;
        }
      }
      last = c;
    });
    f.hold(300);
    f.press(6);  // arm (base button 7), stick centred
  }
  // A mode command (as `tiller-rov-control --mode` sends it), delivered now.
  void command(std::int8_t mode) {
    controller_mode_t m{};
    m.utime = f.t;
    m.mode = mode;
    m.source = "tiller-rov-control";
    f.ex.inject(channels::kMode, m, f.t);
  }
  // Runs `ms` with the stick as it is, calling `each` every 10 ms.
  void run(int ms, const std::function<void()>& each = {}) {
    for (int k = 0; k < ms / 10; ++k) {
      f.hold(10);
      if (each) each();
    }
  }
  const sim::Vector6& eta() const { return sim.model().eta(); }
  const sim::Vector6& nu() const { return sim.model().nu(); }
  double depth() const { return eta()[2]; }
  void reset_step() { max_step = 0; }

  Flight f;
  SimNode sim;
  control::RovControlNode rov;
  std::unique_ptr<nav::NavNode> nav;  // with dvl_nav
  thruster_command_t last{};
  double max_step = 0;
  TimeUs max_step_at = 0;
};

// Largest change of any thruster's thrust (N, the simulator's target from the ESC output)
// between two 10 ms samples over `ms`, calling `each` (if any) after every sample.
inline double thrust_step(RovRig& r, int ms, const std::function<void()>& each = {}) {
  const int n = r.sim.vehicle().size();
  std::vector<double> before(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) before[static_cast<std::size_t>(i)] = r.sim.commanded_thrust(i);
  double worst = 0;
  r.run(ms, [&] {
    for (int i = 0; i < n; ++i) {
      const double t = r.sim.commanded_thrust(i);
      worst = std::max(worst, std::fabs(t - before[static_cast<std::size_t>(i)]));
      before[static_cast<std::size_t>(i)] = t;
    }
    if (each) each();
  });
  return worst;
}

// Peak-to-peak of a series.
inline double p2p(const std::vector<double>& v) {
  if (v.empty()) return 0;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  return *hi - *lo;
}

// Peak-to-peak of a series less its least-squares straight line: what swings, not what drifts.
inline double swing(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  if (v.size() < 2) return 0;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double x = static_cast<double>(k);
    sx += x, sy += v[k], sxx += x * x, sxy += x * v[k];
  }
  const double b = (n * sxy - sx * sy) / (n * sxx - sx * sx), a = (sy - b * sx) / n;
  std::vector<double> r(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) r[k] = v[k] - a - b * static_cast<double>(k);
  return p2p(r);
}

inline double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0 : std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace tiller::e2e
