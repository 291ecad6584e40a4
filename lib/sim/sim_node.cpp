#include "sim/sim_node.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "core/angles.hpp"
#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller {

namespace {

std::string resolve_relative(const config::Value& where, const std::string& path,
                             const char* what = "a vehicle file") {
  namespace fs = std::filesystem;
  if (path.empty() || fs::path(path).is_absolute()) return path;
  const fs::path beside = fs::path(where.file()).parent_path() / path;
  if (fs::exists(beside)) return beside.lexically_normal().string();
  if (fs::exists(path)) return path;
  where.fail(std::string(what) +
             " (relative to the config's folder or the current directory): " + path + " not found");
}

TimeUs period_from_rate(const config::Value& root, std::string_view key, TimeUs step_us) {
  const double hz = root.number(key, {0.01, 1000.0});
  const TimeUs period = from_hz(hz);
  if (period % step_us != 0) {
    root.at(key).fail("a rate whose period is a whole number of steps (step_s)");
  }
  return period;
}

std::vector<sim::ThrusterGeometry> geometry_of(const Vehicle& v) {
  std::vector<sim::ThrusterGeometry> g;
  for (const auto& t : v.thrusters) g.push_back({t.position, t.direction});
  return g;
}

}  // namespace

SimParams load_sim_params(const config::Value& root) {
  SimParams p;
  p.vehicle_file = resolve_relative(root, root.string("vehicle"));
  // RK4 at <= 10 ms (docs/adding-a-vehicle.md) (the ROV's 50 ms thruster lag is integrated exactly,
  // but its fast roll and pitch modes are not; model_test flies every vehicle file at 10 ms).
  const double step_s = root.number_or("step_s", 0.01, {1e-4, 0.01});
  p.step_us = from_seconds(step_s);
  p.odometry_period_us = period_from_rate(root, "odometry_rate_hz", p.step_us);
  p.ground_truth_period_us = period_from_rate(root, "ground_truth_rate_hz", p.step_us);
  p.sim_state_period_us = period_from_rate(root, "sim_state_rate_hz", p.step_us);
  p.esc_timeout_us = from_seconds(root.number("esc_timeout_s", {0.01, 60.0}));
  p.esc_timeout_model = root.choice_or("esc_timeout_model", "safe", {"safe", "hardware"}) == "safe"
                            ? SimParams::EscTimeoutModel::kSafe
                            : SimParams::EscTimeoutModel::kHardware;
  if (auto pulse = root.find("pulse_us")) {
    p.pulse_min_us = pulse->number("min", {500, 2500});
    p.pulse_neutral_us = pulse->number("neutral", {500, 2500});
    p.pulse_max_us = pulse->number("max", {500, 2500});
    if (!(p.pulse_min_us < p.pulse_neutral_us && p.pulse_neutral_us < p.pulse_max_us))
      pulse->fail("min < neutral < max");
  }
  p.throttle_full_scale = root.number_or("throttle_full_scale", 32767, {1, 32767});
  p.max_steps_per_tick = static_cast<int>(root.integer_or("max_steps_per_tick", 100, 1, 100000));
  if (auto init = root.find("initial")) {
    if (init->has("position_m")) {
      const auto pos = init->numbers("position_m", 3, {-1e6, 1e6});
      for (int i = 0; i < 3; ++i) p.initial_eta[i] = pos[static_cast<std::size_t>(i)];
    }
    p.initial_eta[3] = init->angle_deg_or("roll_deg", 0.0, {-90, 90});
    p.initial_eta[4] = init->angle_deg_or("pitch_deg", 0.0, {-89, 89});
    p.initial_eta[5] = wrap_pi(init->angle_deg_or("heading_deg", 0.0, {-360, 360}));
    if (init->has("velocity")) {
      const auto nu = init->numbers("velocity", 6, {-20, 20});
      for (int i = 0; i < 6; ++i) p.initial_nu[i] = nu[static_cast<std::size_t>(i)];
    }
  }
  p.seed = static_cast<std::uint64_t>(root.integer_or("seed", 1, 0));
  if (auto c = root.find("current")) {
    const auto model = c->choice("model", {"none", "constant", "gauss_markov"});
    using M = sim::CurrentParams::Model;
    p.current.model = model == "none"       ? M::kNone
                      : model == "constant" ? M::kConstant
                                            : M::kGaussMarkov;
    // Every known key is read and range-checked whatever the model (so a typo is refused, and
    // switching the model in a file that lists them all just works); a model requires the keys
    // it uses, and ignores the others.
    const bool used = p.current.model != M::kNone;
    const bool gm = p.current.model == M::kGaussMarkov;
    auto num = [&](std::string_view key, bool required, config::Range r) {
      return required ? c->number(key, r) : c->number_or(key, 0.0, r);
    };
    auto deg = [&](std::string_view key, bool required, config::Range r) {
      return required ? c->angle_deg(key, r) : c->angle_deg_or(key, 0.0, r);
    };
    const double speed = num("speed_m_s", used, {0.0, 5.0});
    const double toward = deg("toward_deg", used, {-360, 360});
    const double mu = num("mu_per_s", gm, {gm ? 1e-6 : 0.0, 10.0});
    const double speed_std = num("speed_std_m_s", gm, {0.0, 5.0});
    const double dir_std = deg("direction_std_deg", gm, {0.0, 180.0});
    const double speed_max = num("speed_max_m_s", gm, {0.0, 10.0});
    if (used) {
      p.current.speed_m_s = speed;
      p.current.toward_rad = wrap_pi(toward);
      p.current.speed_max_m_s = speed;
    }
    if (gm && speed_max < speed) {
      // The walk is saturated at speed_max: below the mean it would be a constant current.
      c->at("speed_max_m_s").fail("a saturation >= speed_m_s (" + std::to_string(speed) + " m/s)");
    }
    if (gm) {
      p.current.mu_per_s = mu;
      p.current.speed_std_m_s = speed_std;
      p.current.direction_std_rad = dir_std;
      p.current.speed_max_m_s = speed_max;
    }
  }
  if (auto w = root.find("wind")) {
    p.wind_enabled = w->boolean("enabled");
    const auto e = w->at("enabled");
    p.wind_enabled_key = e.file() + ":" + std::to_string(e.line()) + ": " + e.path();
    p.wind.speed_m_s = w->number_or("speed_m_s", 0.0, {0.0, 50.0});
    p.wind.from_rad = wrap_pi(w->angle_deg_or("from_deg", 0.0, {-360, 360}));
  }
  if (auto n = root.find("odometry_noise")) {
    p.noise.position_std_m = n->number_or("position_std_m", 0.0, {0.0, 100.0});
    p.noise.orientation_std_rad = n->angle_deg_or("orientation_std_deg", 0.0, {0.0, 90.0});
    p.noise.linear_velocity_std_m_s = n->number_or("linear_velocity_std_m_s", 0.0, {0.0, 10.0});
    p.noise.angular_velocity_std_rad_s =
        n->angle_deg_or("angular_velocity_std_deg", 0.0, {0.0, 90.0});
  }
  if (auto d = root.find("disturbance")) {
    if (auto f = d->find("force_step")) {
      p.force_step.enabled = true;
      p.force_step.at_us = from_seconds(f->number("at_s", {0.0, 1e7}));
      const auto n = f->numbers("force_ned", 3, {-1e4, 1e4});
      p.force_step.force_ned = sim::Vector3(n[0], n[1], n[2]);
      p.force_step_key = f->file() + ":" + std::to_string(f->line()) + ": " + f->path();
    }
  }
  p.publish_odometry = root.choice_or("odometry", "truth", {"truth", "estimated"}) == "truth";
  if (root.has("sensors")) {
    const std::string f = root.string("sensors");
    if (f != "none") {
      const std::string path = resolve_relative(root.at("sensors"), f, "a sensors file");
      p.sensors = sim::load_sensor_file(path, p.step_us);
    }
  }
  return p;
}

SimVehicle load_sim_vehicle_file(const std::string& path) {
  const auto root = config::Value::load_file(path);
  SimVehicle v{load_vehicle(root), {}};
  v.vehicle.source_file = path;
  v.dynamics = sim::load_dynamics(root.at("dynamics"));
  root.check_all_used();
  if (!v.dynamics.simulator_thrust_curve.empty()) {
    // The motors' real curve for the simulator's copy; the mixer keeps the file's `curve`.
    const ThrustCurve c = ThrustCurve::preset(v.dynamics.simulator_thrust_curve);
    for (auto& t : v.vehicle.thrusters) t.curve = c;
  }
  return v;
}

namespace {
SimParams load_params_file(const std::string& path) {
  const auto root = config::Value::load_file(path);
  auto p = load_sim_params(root);
  root.check_all_used();
  return p;
}
}  // namespace

sim::DynamicsParams scaled_dynamics(const sim::DynamicsParams& d, const SimParams& p) {
  sim::DynamicsParams s = d;
  s.mass_matrix *= p.mass_scale;
  s.coriolis_mass_matrix *= p.mass_scale;
  if (s.kind == sim::ModelKind::kSurface3Dof) {  // the unused diagonal stays 1 (dynamics.hpp)
    for (const int i : {2, 3, 4}) {
      s.mass_matrix(i, i) = d.mass_matrix(i, i);
      s.coriolis_mass_matrix(i, i) = d.coriolis_mass_matrix(i, i);
    }
  }
  s.linear_damping *= p.damping_scale;
  s.quadratic_damping *= p.damping_scale;
  s.cross_flow.cd *= p.damping_scale;
  return s;
}

SimNode::SimNode(const std::string& config_path)
    : SimNode(load_params_file(config_path),
              load_sim_vehicle_file(load_params_file(config_path).vehicle_file)) {}

SimNode::SimNode(const SimParams& params, const SimVehicle& v)
    : Node("sim", params.step_us),
      p_(params),
      vehicle_(v.vehicle),
      model_(scaled_dynamics(v.dynamics, params), geometry_of(v.vehicle)),
      current_(params.current, params.seed),
      noise_(params.noise, params.seed + 0x9E3779B97F4A7C15ull),
      sensors_(params.sensors, params.seed),
      surface_(v.dynamics.kind == sim::ModelKind::kSurface3Dof),
      esc_fresh_(params.esc_timeout_us) {
  if (!p_.initial_eta.allFinite() || !p_.initial_nu.allFinite())
    throw std::invalid_argument("SimNode: the initial pose and velocity must be finite");
  if (p_.wind_enabled && !surface_) {
    throw config::Error(p_.wind_enabled_key + ": expected false: the vehicle " + v.vehicle.name +
                        " (" + v.vehicle.source_file +
                        ") is underwater_6dof and the wind model acts on surface vessels only");
  }
  if (p_.wind_enabled && v.dynamics.wind_coefficients.isZero()) {
    throw config::Error(p_.wind_enabled_key + ": expected false: the vehicle " + v.vehicle.name +
                        " (" + v.vehicle.source_file +
                        ") has no dynamics.wind_coefficients, so the wind would do nothing");
  }
  if (p_.force_step.enabled && surface_) {
    throw config::Error(p_.force_step_key + ": expected no force step: the vehicle " +
                        v.vehicle.name + " (" + v.vehicle.source_file +
                        ") is surface_3dof and the outside force acts on underwater_6dof "
                        "vehicles only");
  }
  if (p_.force_step.enabled && !p_.force_step.force_ned.allFinite())
    throw std::invalid_argument("SimNode: the force step must be finite");
  subscribe(channels::kEscOutput, &SimNode::on_esc_output);
  if (p_.publish_odometry) {  // else tiller-nav's, with its datum
    advertise<odometry_t>(channels::kOdometry);
    advertise<datum_t>(channels::kDatum);
  }
  advertise<odometry_t>(channels::kGroundTruth);
  advertise<sim_state_t>(channels::kSimState);
  advertise<gnss_fix_t>(channels::kGnss);
  advertise<imu_t>(channels::kImu);
  advertise<heading_t>(channels::kHeading);
  advertise<pressure_t>(channels::kPressure);
  advertise<power_t>(channels::kPower);
  advertise<leak_t>(channels::kLeak);
  advertise<dvl_t>(channels::kDvl);
  if (sensors_.enabled()) {
    sensors_.set_drop_counters(
        &counter("sensors.gnss.dropped"), &counter("sensors.imu.dropped"),
        &counter("sensors.heading.dropped"), &counter("sensors.pressure.dropped"),
        &counter("sensors.power.dropped"), &counter("sensors.leak.dropped"),
        p_.sensors.dvl_timing.enabled ? &counter("sensors.dvl.dropped") : nullptr);
  }
  rej_name_ = &counter("rejected.esc_output.unknown_thruster");
  rej_unit_ = &counter("rejected.esc_output.unit");
  rej_range_ = &counter("rejected.esc_output.out_of_range");
  rej_count_ = &counter("rejected.esc_output.n_channels");
  overruns_ = &counter("overrun.steps_skipped");
  non_finite_ = &counter("fault.state_not_finite");
  model_.reset(p_.initial_eta, p_.initial_nu);
  state_.n_thrusters = vehicle_.size();
  for (const auto& t : vehicle_.thrusters) state_.names.push_back(t.name);
  state_.thrust.assign(static_cast<std::size_t>(vehicle_.size()), 0.0);
  set_health(heartbeat_t::STATE_DEGRADED, "no ESC output yet: zero thrust");
}

bool SimNode::motor_command(std::int8_t unit, std::int32_t value, double& out) const {
  if (unit == esc_output_t::UNIT_THROTTLE_INT16) {
    if (value < -32768 || value > 32767) return false;
    out = std::clamp(static_cast<double>(value) / p_.throttle_full_scale, -1.0, 1.0);
    return true;
  }
  if (unit == esc_output_t::UNIT_PULSE_US) {
    if (value < 500 || value > 2500) return false;
    const double v = value;
    const double u = v >= p_.pulse_neutral_us
                         ? (v - p_.pulse_neutral_us) / (p_.pulse_max_us - p_.pulse_neutral_us)
                         : (v - p_.pulse_neutral_us) / (p_.pulse_neutral_us - p_.pulse_min_us);
    out = std::clamp(u, -1.0, 1.0);
    return true;
  }
  return false;
}

void SimNode::on_esc_output(const esc_output_t& m, TimeUs now) {
  if (!on_time(esc_fresh_, m.utime, now, "esc_output")) return;
  const int n = m.n_channels;
  if (n < 0 || n > sim::kMaxThrusters || static_cast<int>(m.names.size()) != n ||
      static_cast<int>(m.value.size()) != n) {
    reject(*rej_count_);
    return;
  }
  if (m.unit != esc_output_t::UNIT_THROTTLE_INT16 && m.unit != esc_output_t::UNIT_PULSE_US) {
    reject(*rej_unit_);
    return;
  }
  if (checks::check(m) != nullptr) {  // the rest of its contract: values, normalized in [-1, 1]
    reject(*rej_range_);
    return;
  }
  // A thrust curve that depends on the supply voltage (curve: t200) follows the simulated
  // battery's bus voltage when the sensors are on (no effect on other curves; no allocation).
  if (sensors_.enabled())
    for (auto& th : vehicle_.thrusters) th.curve.set_supply_voltage(sensors_.battery().voltage());
  std::array<double, sim::kMaxThrusters> target{};
  for (int c = 0; c < n; ++c) {
    const auto k = static_cast<std::size_t>(c);
    const int i = vehicle_.index_of(m.names[k]);
    if (i < 0) {
      reject(*rej_name_);
      return;
    }
    double motor = 0;
    if (!motor_command(m.unit, m.value[k], motor)) {
      reject(*rej_range_);
      return;
    }
    const Thruster& t = vehicle_.thrusters[static_cast<std::size_t>(i)];
    // tiller-esc flipped a reversed thruster's hardware sign; undo it to get Tiller's command.
    const double u = t.reversed ? -motor : motor;
    target[static_cast<std::size_t>(i)] = m.armed ? t.thrust_from_command(u) : 0.0;
  }
  commanded_ = target;
  if (p_.esc_timeout_model == SimParams::EscTimeoutModel::kHardware) {
    esc_fresh_.set_limit(m.unit == esc_output_t::UNIT_THROTTLE_INT16 ? SimParams::kTgyHoldUs
                                                                     : SimParams::kForeverUs);
  }
  esc_fresh_.mark(now, m.utime, clock_offset());
}

void SimNode::on_tick(TimeUs now) {
  const bool fresh = esc_fresh_.fresh(now);
  if (esc_fresh_.stale_events() != stale_seen_) {
    count_stale(esc_fresh_.stale_events() - stale_seen_);
    stale_seen_ = esc_fresh_.stale_events();
  }
  if (fresh != esc_was_fresh_ || !started_) {
    if (fresh) {
      set_health(heartbeat_t::STATE_OK, "running");
    } else {
      set_health(heartbeat_t::STATE_DEGRADED, esc_fresh_.ever() ? "ESC output stale: zero thrust"
                                                                : "no ESC output yet: zero thrust");
    }
    esc_was_fresh_ = fresh;
  }
  for (int i = 0; i < model_.n_thrusters(); ++i)
    model_.set_thrust_target(i, fresh ? commanded_[static_cast<std::size_t>(i)] : 0.0);

  if (!started_) {
    started_ = true;
    sim_time_ = now;
    start_time_ = now;
  }
  std::int64_t steps = (now - sim_time_) / p_.step_us;
  if (steps > p_.max_steps_per_tick) {
    *overruns_ += steps - p_.max_steps_per_tick;
    steps = p_.max_steps_per_tick;
    sim_time_ = now - steps * p_.step_us;
  }
  const double dt = to_seconds(p_.step_us);
  sim::Environment env;
  env.wind = p_.wind_enabled;
  env.wind_ned = p_.wind.velocity_ned();
  const TimeUs step_at = start_time_ + p_.force_step.at_us;
  for (std::int64_t k = 0; k < steps; ++k) {
    // The step force acts on every step that starts at or after its time.
    env.force_ned = disturbance_;
    if (p_.force_step.enabled && sim_time_ >= step_at) env.force_ned += p_.force_step.force_ned;
    current_.step(dt);
    env.current_ned = current_.velocity_ned();
    const sim::Vector6 nu_before = model_.nu();
    model_.step(dt, env);
    sim_time_ += p_.step_us;
    if (sensors_.enabled()) sense(nu_before, dt);
  }
  if (!model_.eta().allFinite() || !model_.nu().allFinite()) {
    // Cannot happen with valid parameters; if it does, restart at rest rather than publish NaN.
    ++*non_finite_;
    set_health(heartbeat_t::STATE_FAULT, "state not finite: reset to the initial pose");
    model_.reset(p_.initial_eta, sim::Vector6::Zero());
  }
  publish_outputs(now);
}

void SimNode::sense(const sim::Vector6& nu_before, double dt) {
  sim::TrueState s;
  s.eta = model_.eta();
  s.nu = model_.nu();
  // d/dt [u v w] over the step + omega x [u v w]: the acceleration relative to NED, in body.
  s.accel_body = (s.nu.head<3>() - nu_before.head<3>()) / dt + s.nu.tail<3>().cross(s.nu.head<3>());
  for (int i = 0; i < model_.n_thrusters(); ++i)
    thrust_now_[static_cast<std::size_t>(i)] = model_.thrust(i);
  s.thrust = thrust_now_.data();
  s.n_thrusters = model_.n_thrusters();
  sensors_.step(sim_time_, dt, s);
}

void SimNode::fill_odometry(odometry_t& o, const sim::Vector6& eta, const sim::Vector6& nu,
                            TimeUs now) {
  o.utime = now;
  o.valid = odometry_t::VALID_ALL;  // the simulator's state (truth, or truth + noise) is whole
  for (int i = 0; i < 3; ++i) {
    o.position[i] = eta[i];
    o.orientation[i] = eta[3 + i];
  }
  for (int i = 0; i < 6; ++i) o.velocity[i] = nu[i];
  o.n_pose_cov = 0;
  o.n_velocity_cov = 0;
}

void SimNode::publish_outputs(TimeUs now) {
  const sim::Vector3 c = current_.velocity_ned();
  // Due when the simulated time reaches the next multiple of the period (live ticks come at
  // wall-clock times, lockstep ticks exactly on the step grid).
  auto due = [this](TimeUs& next, TimeUs period) {
    if (sim_time_ < next) return false;
    next = (sim_time_ / period + 1) * period;
    return true;
  };
  if (due(next_truth_, p_.ground_truth_period_us)) {
    fill_odometry(truth_, model_.eta(), model_.nu(), now);
    publish(channels::kGroundTruth, truth_);
  }
  sensors_.release(now, [this](const char* channel, const auto& m) { publish(channel, m); });
  if (due(next_odom_, p_.odometry_period_us) && p_.publish_odometry) {
    sim::Vector6 eta = model_.eta();
    sim::Vector6 nu = model_.nu();
    noise_.apply(eta, nu);
    if (surface_) {
      eta[2] = eta[3] = eta[4] = 0;
      nu[2] = nu[3] = nu[4] = 0;
    }
    fill_odometry(odom_, eta, nu, now);
    publish(channels::kOdometry, odom_);
  }
  if (p_.publish_odometry && due(next_datum_, kUsPerSecond)) {
    datum_t d{};  // the local frame's origin, as the simulated GNSS has it
    d.utime = now;
    d.latitude = p_.sensors.gnss.datum_latitude_deg;
    d.longitude = p_.sensors.gnss.datum_longitude_deg;
    d.altitude = p_.sensors.gnss.datum_altitude_m;
    d.source = datum_t::SOURCE_CONFIG;
    publish(channels::kDatum, d);
  }
  if (due(next_state_, p_.sim_state_period_us)) {
    state_.utime = now;
    const sim::Vector6 nu_r = model_.nu_relative(c);
    for (int i = 0; i < 6; ++i) {
      state_.eta[i] = model_.eta()[i];
      state_.nu[i] = model_.nu()[i];
      state_.nu_r[i] = nu_r[i];
    }
    for (int i = 0; i < 3; ++i) state_.current_ned[i] = c[i];
    for (int i = 0; i < model_.n_thrusters(); ++i)
      state_.thrust[static_cast<std::size_t>(i)] = model_.thrust(i);
    publish(channels::kSimState, state_);
  }
}

}  // namespace tiller
