#include "runtool/run.hpp"

#include <tiller/arm_request_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include <algorithm>
#include <cmath>

#include <filesystem>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "control/control_config.hpp"
#include "control/rov_config.hpp"
#include "control/rov_node.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "esc/esc_config.hpp"
#include "esc/esc_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mixer/mixer_node.hpp"
#include "nav/nav_node.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/log.hpp"
#include "sim/sim_node.hpp"
#include "sim/sim_options.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller::runtool {

namespace fs = std::filesystem;

Setting parse_setting(const std::string& text) {
  const auto eq = text.find('=');
  const auto dot = text.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq)
    throw std::runtime_error("expected FILE.KEY=VALUE (FILE one of " + std::string(kSettingFiles) +
                             ", e.g. control.velocity_pid.yaw.k_error=40), got '" + text + "'");
  Setting s{text.substr(0, dot), text.substr(dot + 1, eq - dot - 1), text.substr(eq + 1)};
  bool known = false;
  for (const char* f : {"sim", "esc", "mixer", "control", "guidance", "nav"}) known |= s.file == f;
  if (!known)
    throw std::runtime_error("'" + text + "': expected the file to be one of " +
                             std::string(kSettingFiles) + ", got '" + s.file + "'");
  return s;
}

namespace {

std::string existing(const std::string& given, const std::string& fallback, const char* option) {
  const std::string path = app::resolve_path(given.empty() ? fallback : given);
  if (!fs::exists(path)) {
    throw std::runtime_error(
        "--" + std::string(option) + ": " + path + ": no such file" +
        (given.empty() ? " (the default for this vehicle; give --" + std::string(option) + " FILE)"
                       : ""));
  }
  return path;
}

config::Value load(const std::string& path, const std::string& file,
                   const std::vector<Setting>& settings) {
  const auto root = config::Value::load_file(path);
  for (const auto& s : settings) {
    if (s.file == file) root.set(s.key, s.value);
  }
  return root;
}

}  // namespace

RunFiles resolve_files(const RunSpec& spec) {
  RunFiles f;
  if (spec.mission_file.empty()) throw std::runtime_error("no mission file given");
  f.mission = existing(spec.mission_file, "", "mission");
  f.vehicle = existing(spec.vehicle_file, "", "vehicle");
  const std::string v = fs::path(f.vehicle).stem().string();
  f.sim = existing(spec.sim_file, "", "sim");
  f.esc = existing(spec.esc_file, "config/esc/" + v + "_sim.yaml", "esc");
  f.mixer = existing(spec.mixer_file, "config/mixer/" + v + ".yaml", "mixer");
  f.control = existing(spec.control_file, "config/control/" + v + ".yaml", "control");
  f.guidance = existing(spec.guidance_file, "config/guidance/" + v + ".yaml", "guidance");
  return f;
}

RunOutcome run(const RunSpec& spec) {
  RunOutcome out;
  out.files = resolve_files(spec);
  const RunFiles& f = out.files;
  const auto m = mission::load_mission_file(f.mission);

  // tiller-sim with --vehicle, --mission and the given options, as the launch file starts it.
  // On estimated state without --sensors: the vehicle kind's simulated sensors.
  const SimVehicle sv = load_sim_vehicle_file(f.vehicle);
  const bool surface = sv.dynamics.kind == sim::ModelKind::kSurface3Dof;
  std::vector<std::string> args = {"--vehicle", f.vehicle, "--mission", f.mission};
  args.insert(args.end(), spec.sim_args.begin(), spec.sim_args.end());
  const auto& a = spec.sim_args;
  const auto odometry = std::find(a.begin(), a.end(), "--odometry");
  const bool estimated =
      odometry != a.end() && odometry + 1 != a.end() && odometry[1] == "estimated";
  if (estimated && std::find(a.begin(), a.end(), "--sensors") == a.end()) {
    out.files.sensors =
        app::resolve_path(surface ? "config/sim/sensors/usv.yaml" : "config/sim/sensors/rov.yaml");
    args.push_back("--sensors");
    args.push_back(out.files.sensors);
  }
  const SimOverrides so = sim_overrides(args);
  const auto sroot = load(f.sim, "sim", spec.settings);
  SimParams sp = load_sim_params(sroot);
  sroot.check_all_used();
  apply(so, sp);
  out.estimated = !sp.publish_odometry;
  out.start_north = sp.initial_eta[0];
  out.start_east = sp.initial_eta[1];
  out.start_heading = sp.initial_eta[5];
  SimNode sim(sp, sv);
  std::unique_ptr<nav::NavNode> navn;
  if (out.estimated) {
    // An ROV's estimate for a mission: on the DVL (its position), as config/launch/
    // sim_bluerov2_dvl.yaml runs it.
    out.files.nav = existing(
        spec.nav_file, surface ? "config/nav/usv_sim.yaml" : "config/nav/rov_dvl.yaml", "nav");
    const auto nroot = load(out.files.nav, "nav", spec.settings);
    navn = std::make_unique<nav::NavNode>(nav::load_nav_params(nroot));
    nroot.check_all_used();
  }

  const esc::EscConfig ec = esc::load_esc_config(load(f.esc, "esc", spec.settings));
  if (ec.backend != "sim")
    throw std::runtime_error(f.esc +
                             ": backend: expected sim (tiller-run drives the simulator), "
                             "got '" +
                             ec.backend + "'");
  EscNode esc(ec.node, esc::make_backend(ec));

  const auto mroot = load(f.mixer, "mixer", spec.settings);
  const MixerParams mp = load_mixer_params(mroot);
  mroot.check_all_used();
  MixerNode mixer(mp, load_vehicle_file(mp.vehicle_file));

  // A boat: the velocity PID and station keeping (the arbiter in the PID's node). An ROV:
  // tiller-rov-control, in waypointing (the mission's TILLER_MODE), from its own control file.
  // The simulator's truth odometry carries no covariance, which tiller-rov-control's position
  // modes require of an estimate: on truth, an ROV's run lifts that requirement (and so writes no
  // replay manifest, see replay_manifest).
  std::vector<Setting> settings = spec.settings;
  if (!surface && !out.estimated)
    settings.push_back({"control", "rov_control.position.require_covariance", "false"});
  const auto croot = load(f.control, "control", settings);
  std::unique_ptr<control::VelocityPidNode> vpid;
  std::unique_ptr<control::StationKeepNode> skeep;
  std::unique_ptr<control::RovControlNode> rovc;
  if (surface) {
    vpid =
        std::make_unique<control::VelocityPidNode>(control::load_velocity_pid_node_params(croot));
    skeep =
        std::make_unique<control::StationKeepNode>(control::load_station_keep_node_params(croot));
  } else {
    rovc = std::make_unique<control::RovControlNode>(control::load_rov_control(croot));
    if (auto d = croot.find("description")) d->mark_used();
    croot.check_all_used();
  }

  const auto groot = load(f.guidance, "guidance", spec.settings);
  const auto fparams = guidance::load_follower_node_params(groot);
  groot.check_all_used();
  out.max_speed = fparams.follower.max_speed;
  guidance::PathFollowerNode follower(fparams);

  mission::MissionNode mnode(m, 1, kUsPerSecond, true, spec.start_gate);
  // A mission with items (mission/sequencer.hpp) is complete when its last leg is: held or
  // stopped, not at its first leg's end.
  const mission::Sequencer* seq = mnode.sequencer();

  // The order of the closed-loop harness (test/autonomy/harness.cpp): plant, then autonomy.
  LockstepExecutor ex(0);
  ex.add(sim);
  if (navn) ex.add(*navn);  // the estimator right after the plant, as the sensors' consumer
  const auto add_autonomy = [&] {
    for (Node* n : std::initializer_list<Node*>{&esc, &mixer, &mnode, &follower}) ex.add(*n);
    if (surface) {
      ex.add(*vpid);
      ex.add(*skeep);
    } else {
      ex.add(*rovc);
    }
  };
  const TimeUs settle = from_seconds(std::max(spec.settle_s, 0.0));
  if (settle == 0) add_autonomy();

  std::unique_ptr<LogWriter> log;
  if (!spec.log_file.empty()) {
    std::error_code ec_rm;
    fs::remove(spec.log_file, ec_rm);  // lcm::LogFile appends; a run's log holds only that run
    log = std::make_unique<LogWriter>(spec.log_file);
  }
  std::vector<Event> scored;
  std::vector<scores::Goal> goals;  // the mission's path, as the scores take it
  for (const auto& w : m.waypoints)
    goals.push_back({w.north, w.east, w.has_heading, w.heading, w.depth});
  out.rov = !surface;
  odometry_t gt;
  double depth_sq = 0;
  std::size_t depth_n = 0;
  path_progress_t pr;
  velocity_setpoint_t vsp;
  odometry_t od;
  arm_request_t ar;
  thruster_command_t tc;
  constexpr std::int32_t kNeeded = int{odometry_t::VALID_POSITION} |
                                   int{odometry_t::VALID_VELOCITY} |
                                   int{odometry_t::VALID_ATTITUDE};
  bool was_valid = false;
  TimeUs last_odom = -1;
  double last_pos[2] = {0, 0};
  bool had_position = false;
  bool was_dr = false;
  TimeUs recovered_at = -1;  // DEAD_RECKONING cleared (-1: not yet)
  std::vector<double> last_cmd;
  TimeUs invalid_since = -1;  // the first invalid odometry after a valid one (-1: valid)
  // The controllers' odometry_timeout_s (0.5 s) and one mixer period (20 ms): from then on the
  // thrust must be neutral while the estimate stays invalid.
  constexpr TimeUs kNeutralAfter = 520'000;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    ++out.messages;
    if (seq != nullptr && !out.completed &&
        (seq->state() == mission::Sequencer::State::kHolding ||
         seq->state() == mission::Sequencer::State::kStopped) &&
        !seq->fence_breached()) {
      out.completed = true;
      out.completed_at = to_seconds(t);
    }
    if (log) log->write(ch, d, n, t);
    if (ch == channels::kVelocitySetpoint && vsp.decode(d, 0, n) == n && vsp.active) {
      out.max_setpoint_speed =
          std::max(out.max_setpoint_speed, std::hypot(vsp.velocity[0], vsp.velocity[1]));
    }
    if (ch == channels::kArmRequest && ar.decode(d, 0, n) == n && !ar.arm) ++out.disarm_requests;
    if (invalid_since >= 0 && t - invalid_since > kNeutralAfter &&
        ch == channels::kThrusterCommand && tc.decode(d, 0, n) == n) {
      for (const double c : tc.command)
        out.invalid_thrust_max = std::max(out.invalid_thrust_max, std::fabs(c));
    }
    if (recovered_at >= 0 && t - recovered_at <= 10'000'000 && ch == channels::kThrusterCommand &&
        tc.decode(d, 0, n) == n) {
      if (last_cmd.size() == tc.command.size())
        for (std::size_t i = 0; i < last_cmd.size(); ++i)
          out.recovery_command_step =
              std::max(out.recovery_command_step, std::fabs(tc.command[i] - last_cmd[i]));
      last_cmd = tc.command;
    }
    if (out.estimated && ch == channels::kOdometry && od.decode(d, 0, n) == n) {
      const double dt = last_odom >= 0 ? to_seconds(t - last_odom) : 0.0;
      const bool has_position = od.valid & odometry_t::VALID_POSITION;
      if (last_odom >= 0 && has_position && had_position)  // both with a valid position
        out.max_position_step_m =
            std::max(out.max_position_step_m,
                     std::hypot(od.position[0] - last_pos[0], od.position[1] - last_pos[1]));
      had_position = has_position;
      last_pos[0] = od.position[0];
      last_pos[1] = od.position[1];
      const bool dr = od.valid & odometry_t::DEAD_RECKONING;
      if (was_dr && !dr) recovered_at = t;
      was_dr = dr;
      last_odom = t;
      const bool valid = (od.valid & kNeeded) == kNeeded;
      if (od.valid & odometry_t::DEAD_RECKONING) out.dead_reckoning_s += dt;
      if (was_valid && !valid) out.odometry_invalid_s += dt;
      if (was_valid && !valid && invalid_since < 0) invalid_since = t;
      if (valid) invalid_since = -1;
      was_valid |= valid;
    }
    if (out.rov && mnode.began_at() >= 0 && ch == channels::kGroundTruth &&
        gt.decode(d, 0, n) == n) {
      const double err =
          gt.position[2] - scores::depth_on_path(gt.position[0], gt.position[1], goals);
      if (out.depth_from_s < 0 && std::fabs(err) <= 0.1) out.depth_from_s = to_seconds(t);
      if (out.depth_from_s >= 0) {
        depth_sq += err * err;
        ++depth_n;
        out.depth_max_m = std::max(out.depth_max_m, std::fabs(err));
      }
    }
    if (ch == channels::kGroundTruth || ch == channels::kOdometry || ch == channels::kPath ||
        ch == channels::kPathProgress) {
      scored.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
      if (ch == channels::kPathProgress && seq == nullptr && !out.completed &&
          pr.decode(d, 0, n) == n && pr.complete) {
        out.completed = true;
        out.completed_at = to_seconds(t);
      }
    }
  });

  const double hold = spec.hold_s >= 0 ? spec.hold_s : m.station_keep_s;
  const TimeUs limit = from_seconds(spec.time_limit_s >= 0 ? spec.time_limit_s : m.time_limit_s);
  const TimeUs wait_limit = settle + from_seconds(std::max(spec.start_wait_s, 0.0));
  TimeUs t = 0;
  if (settle > 0) {
    ex.run_until(settle);
    add_autonomy();
    t = settle;
  }
  // The time limit counts from the mission's start (the start gate opening, or at once).
  while (mnode.began_at() < 0 ? t < wait_limit : t < mnode.began_at() + limit) {
    t += kUsPerSecond;
    ex.run_until(t);
    if (out.completed && to_seconds(t) >= out.completed_at + hold) break;
  }
  out.sim_s = to_seconds(t);
  if (depth_n > 0) out.depth_rms_m = std::sqrt(depth_sq / static_cast<double>(depth_n));
  out.started_at = mnode.began_at() >= 0 ? to_seconds(mnode.began_at()) : -1.0;
  out.scores = scores::score_events(scored, goals);
  return out;
}

std::string replay_manifest(const RunSpec& spec, const RunFiles& f) {
  if (!spec.settings.empty() || spec.settle_s > 0) return "";
  const bool surface =
      load_sim_vehicle_file(f.vehicle).dynamics.kind == sim::ModelKind::kSurface3Dof;
  if (!surface && f.nav.empty()) return "";  // an ROV on truth: a setting changed (run())
  std::ostringstream os;
  os << "# Written by tiller-run: the config of each process of this lockstep run.\n"
     << "# A lockstep log: replay must match bit for bit, heartbeats included.\n"
     << "processes:\n"
     << "  sim: {program: tiller-sim, config: " << f.sim << ", args: [--vehicle, " << f.vehicle
     << ", --mission, " << f.mission;
  for (const auto& a : spec.sim_args) os << ", \"" << a << "\"";
  if (!f.sensors.empty()) os << ", --sensors, " << f.sensors;
  os << "]}\n"
     << "  esc: " << f.esc << "\n  mixer: " << f.mixer;
  if (surface)
    os << "\n  velocity-pid: " << f.control << "\n  station-keep: " << f.control;
  else
    os << "\n  rov-control: " << f.control;
  os << "\n  path-follower: " << f.guidance;
  if (!f.nav.empty()) os << "\n  nav: " << f.nav;
  os << "\nheartbeats: true\ntolerance: 0\ntime_tolerance_ms: 0\n";
  return os.str();
}

}  // namespace tiller::runtool
