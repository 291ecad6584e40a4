// tiller-run's logic: one mission file flown on the simulated vehicle in lockstep (simulated
// time, as fast as the CPU goes) by the real node classes of a live simulated run -- tiller-sim,
// tiller-esc (sim backend), tiller-mixer, tiller-mission, tiller-path-follower,
// tiller-velocity-pid, tiller-station-keep -- built from the same config files, optionally
// logged (an LCM log with the channels a live run logs, heartbeats included) and scored as
// tiller-score scores a log (lib/scores/log_scores.hpp).
//
// The run ends when the path is complete and the goal held for the mission's station_keep_s
// (checked at each whole simulated second, as the closed-loop test harness does), or at the
// mission's time_limit_s. Same spec, same messages, bit for bit (no clock, seeded randomness).
// The vehicle starts at the mission's start: pose (tiller-sim --mission); sim_args (tiller-sim's
// options: --current-speed, --current-toward-deg, --seed, --north, ...) win over it.
// On estimated state (sim_args "--odometry estimated") the simulator publishes its sensors
// (--sensors, default config/sim/sensors/usv.yaml or _rov.yaml by the vehicle's kind) and no
// odometry, and tiller-nav's NavNode (nav_file, default config/nav/usv_sim.yaml or
// rov.yaml; usv_sim.yaml has the simulator's datum) makes TILLER_ODOMETRY from them; the scores add
// the estimation error against the ground truth.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mission/start_gate.hpp"
#include "scores/log_scores.hpp"

namespace tiller::runtool {

// One setting changed in one of the run's config files before it is loaded:
// "control.velocity_pid.yaw.k_error=40" is file "control", key "velocity_pid.yaw.k_error",
// value "40" (YAML text). Files: sim, esc, mixer, control, guidance.
struct Setting {
  std::string file, key, value;
  std::string text() const { return file + "." + key + "=" + value; }
};
// Parses FILE.KEY=VALUE; throws std::runtime_error naming what is wrong.
Setting parse_setting(const std::string& text);
// The config files a setting can name.
inline constexpr const char* kSettingFiles = "sim, esc, mixer, control, guidance, nav";

struct RunSpec {
  std::string mission_file;  // YAML or CSV
  std::string vehicle_file = "config/vehicles/otter.yaml";
  std::string sim_file = "config/sim/sim.yaml";
  // Empty: the vehicle's own, config/esc/<vehicle>_sim.yaml, config/mixer/<vehicle>.yaml,
  // config/control/<vehicle>.yaml, config/guidance/<vehicle>.yaml (<vehicle>: the vehicle
  // file's name without .yaml), as config/launch/sim_usv_mission.yaml names them for the Otter.
  std::string esc_file, mixer_file, control_file, guidance_file;
  std::string nav_file;  // estimated state only; empty: config/nav/usv_sim.yaml or rov.yaml
  std::vector<std::string> sim_args;  // tiller-sim options on top ("--current-speed", "0.3", ...)
  std::vector<Setting> settings;
  double hold_s = -1;        // s of station keeping after completion; < 0: the mission's
  double time_limit_s = -1;  // s; < 0: the mission's
  // s before the mission starts: the simulator (and tiller-nav) run alone, the vehicle without
  // ESC, mixer, mission or controllers (no thrust), as an operator waits for the estimate to
  // settle before starting; the time limit counts from the start. 0: all start together.
  double settle_s = 0;
  // tiller-mission's start gate (mission/start_gate.hpp; tiller-run --start-std-m,
  // --start-settle-s): the mission waits for a valid, certain, settled estimate before it
  // publishes its path; the time limit counts from then, and the run gives up waiting at
  // start_wait_s.
  mission::StartGateParams start_gate;
  double start_wait_s = 300;
  std::string log_file;  // empty: no log
};

// The files a run uses, defaults filled in and resolved (app::resolve_path).
struct RunFiles {
  std::string mission, vehicle, sim, esc, mixer, control, guidance;
  std::string nav;      // on estimated state
  std::string sensors;  // on estimated state without --sensors in sim_args: the default added
};
// Throws std::runtime_error naming a file that does not exist and the option that sets it.
RunFiles resolve_files(const RunSpec& spec);

struct RunOutcome {
  RunFiles files;
  scores::RunScores scores;
  bool completed = false;
  double completed_at = -1;       // s
  double sim_s = 0;               // simulated seconds run
  std::size_t messages = 0;       // delivered (and logged)
  double max_setpoint_speed = 0;  // m/s: largest |velocity| of an active TILLER_VELOCITY_SETPOINT
  double max_speed = 0;           // m/s: the follower's max_speed (guidance config)
  double started_at = -1;         // s: when tiller-mission first published the path (-1: never)
  double start_north = 0, start_east = 0, start_heading = 0;  // where the vehicle started
  bool estimated = false;                                     // flown on tiller-nav's odometry
  // On estimated state, from TILLER_ODOMETRY's valid bits (s of simulated time, by sample):
  double dead_reckoning_s = 0;      // DEAD_RECKONING set
  double odometry_invalid_s = 0;    // position, velocity or attitude invalid after the first valid
  std::size_t disarm_requests = 0;  // TILLER_ARM_REQUEST disarms (the mixer's: input lost)
  // The largest |thruster command| (normalised) the mixer published while the odometry had been
  // invalid for more than the controllers' odometry_timeout_s (0.5 s) plus one mixer period:
  // 0 when the controllers give neutral on an invalid estimate.
  double invalid_thrust_max = 0;
  // Back from dead reckoning (estimated state): the largest step of TILLER_ODOMETRY's position
  // between two messages that both have a valid position (m, north-east), and the largest change of
  // one thruster command between two TILLER_THRUSTER_COMMANDs in the 10 s after DEAD_RECKONING
  // cleared (normalised).
  double max_position_step_m = 0;
  double recovery_command_step = 0;
  // An ROV (the vehicle file's model is not the surface one): the true depth against the path's
  // (the mission's waypoint depths, interpolated along the horizontally nearest segment), m,
  // from when the vehicle first comes within 0.1 m of it (the dive from the surface left out)
  // to the end of the run; -1 when it never does or the vehicle is a boat.
  bool rov = false;
  double depth_rms_m = -1, depth_max_m = -1;
  double depth_from_s = -1;  // s: when the depth was first within 0.1 m
};

// Runs it. Config errors throw config::Error (file, line, key); others std::runtime_error.
RunOutcome run(const RunSpec& spec);

// The replay manifest for a logged run (tiller-replay LOG finds LOG's .replay.yaml): each
// process with its config file and the simulator's options. Empty when settings changed a
// config in memory (a replay from the files would compare another controller), or when the run
// settled first (the replay starts every process at once). On estimated state it names
// tiller-nav's config too (and the simulator's sensors file): the estimator replays bit for bit.
std::string replay_manifest(const RunSpec& spec, const RunFiles& files);

}  // namespace tiller::runtool
