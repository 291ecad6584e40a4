// A launch file: the processes of one run (a vehicle, a simulation), how to start them, and
// what to do when one exits. Loaded strictly from YAML (lib/core config): an unknown key, a
// wrong type, a duplicate name, an unknown dependency or a dependency cycle is refused with the
// file, line and key at fault. Times in seconds.
//
//   name: sim-usv-mission
//   lcm_url: udpm://239.255.76.67:7667?ttl=0   # children get it as LCM_DEFAULT_URL and ${LCM_URL}
//   root: ../..                 # working directory of every process, relative to this file
//   grace_s: 3                  # SIGTERM -> SIGKILL delay when stopping
//   ends_with: mission          # the run ends when this process exits (its exit code decides)
//   logger: {enabled: true, dir: logs, channels: ".*", split_mb: 0, rotate: 0}
//   key_file: ${TILLER_KEY_FILE:-$XDG_CONFIG_HOME/tiller/sim.key}  # the vehicle's signing key
//                               # (relative to root; $NAME expands inside a ${X:-fallback}, and
//                               # XDG_CONFIG_HOME defaults to $HOME/.config); children get it as
//                               # TILLER_KEY_FILE (docs/safety.md)
//   require_signed: true        # children refuse unsigned input (TILLER_REQUIRE_SIGNED=1); the
//                               # default with a key_file. false needs allow_unsigned: true too,
//                               # and the launcher prints a WARNING at start
//   allow_unsigned: false       # true: running with unsigned input accepted is meant
//   auth_window_s: 1            # replay window (TILLER_AUTH_WINDOW_S)
//   clock_offset_s: 0.25        # bound on clock offset between computers allowed on a
//                               # message's utime (TILLER_CLOCK_OFFSET_S; docs/safety.md)
//   create_key: false           # true (simulator files only): make key_file if it is missing
//   liveness_s: 3               # every process's default liveness_s (docs/safety.md)
//   processes:
//     - name: sim
//       command: tiller-sim      # looked up next to tiller-launch first, then on PATH
//       args: [--config, config/sim/usv.yaml, "--mission=${MISSION:-config/missions/default.yaml}"]
//       env: {TILLER_X: "1"}
//       group: sim
//       depends_on: [esc]
//       start_delay_s: 0.2
//       restart: on-failure      # never | on-failure | always
//       backoff_s: 0.5           # first restart delay, doubled each time up to backoff_max_s
//       backoff_max_s: 10
//       max_restarts: 5          # then the process is given up on
//       critical: false          # true: giving up on it stops the whole run (exit 3)
//       autostart: true          # false: started only when its group or name is asked for
//                                # (--group / --only), e.g. a mission that arms a real boat
//       liveness_s: 3            # heartbeat silent this long: treated as failed (0: not
//                                # watched; default: the file's liveness_s, itself 3)
//       heartbeat: sim           # the node whose TILLER_HEARTBEAT_<NODE> to watch (default: name)
//       realtime: {priority: 80, lock_memory: true, required: false}
//                                # tiller-* programs only: passed on as --realtime-priority 80
//                                # --lock-memory [--realtime-required]; the program applies it
//                                # itself (runtime/realtime.hpp, docs/operations.md "Real time")
#pragma once

#include <map>
#include <string>
#include <vector>

namespace tiller::config {
class Value;
}

namespace tiller::launch {

enum class Restart { kNever, kOnFailure, kAlways };
const char* to_string(Restart r);

// A process's `realtime:` entry: SCHED_FIFO priority and locked memory, which the program
// applies itself from the flags realtime_args() makes.
struct RealtimeSpec {
  int priority = 0;          // SCHED_FIFO priority 1..99; 0: the normal scheduler
  bool lock_memory = false;  // mlockall (the loader's default with a realtime: entry: true)
  bool required = false;     // true: the program refuses to start when it is not permitted
  bool any() const { return priority > 0 || lock_memory; }
};

// The command-line flags of a realtime: entry (none when !r.any()).
std::vector<std::string> realtime_args(const RealtimeSpec& r);

struct ProcessSpec {
  std::string name;
  std::string command;
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
  std::string group;
  std::vector<std::string> depends_on;
  double start_delay_s = 0.0;
  // Non-empty: once due, the start also waits until this file has data (the launcher sets it
  // on the process after lcm-logger to the log file: nothing runs before the log records it),
  // at most start_after_file_max_s; then it starts anyway, with a warning.
  std::string start_after_file;
  double start_after_file_max_s = 10.0;
  Restart restart = Restart::kNever;
  double backoff_s = 0.5;
  double backoff_max_s = 10.0;
  int max_restarts = 5;
  double stable_after_s = 30.0;  // running this long resets the back-off and the restart count
  bool critical = false;
  bool autostart = true;  // false: only with --group G / --only NAME
  // Liveness (docs/safety.md, "Stalls and liveness"): once the process has published a
  // heartbeat, one silent for liveness_s is treated as failed (stopped, then `restart`
  // applies). 0: not watched. `heartbeat` names the node (heartbeat_t.process) to watch.
  double liveness_s = 3.0;
  std::string heartbeat;  // empty: the process's name
  RealtimeSpec realtime;  // its flags are already at the end of args
  int line = 0;           // line in the launch file (for messages)
  const std::string& heartbeat_node() const { return heartbeat.empty() ? name : heartbeat; }
};

struct LoggerSpec {
  bool enabled = true;
  std::string dir = "logs";     // relative to root
  std::string channels = ".*";  // lcm-logger -c
  // split_mb > 0: a new file every N MB; rotate > 0: keep N files, the newest FILE.0 (with
  // split_mb: at most rotate * split_mb MB of log, bounded on a boot service; the file name is
  // then fixed, <dir>/<launch name>.lcmlog, so the runs of past boots rotate away too).
  // split_mb without rotate: FILE.00, FILE.01, ... (unbounded).
  double split_mb = 0.0;
  int rotate = 0;
};

struct LaunchFile {
  std::string path;  // the file it came from
  std::string name;
  std::string description;
  std::string lcm_url;
  std::string root;  // absolute working directory of every process
  double grace_s = 3.0;
  std::string ends_with;  // process name, or empty
  LoggerSpec logger;
  // Message signing (docs/safety.md, "Who may command"). key_file as written (${VAR}
  // substituted when the run starts, then relative to root); line numbers for messages.
  std::string key_file;
  bool require_signed = false;  // default: true when key_file is set
  bool allow_unsigned = false;  // require_signed: false is meant (a WARNING at start)
  double auth_window_s = 1.0;
  double clock_offset_s = 0.25;  // core/time.hpp kDefaultClockOffsetUs
  bool create_key = false;
  int key_file_line = 0;
  double liveness_s = 3.0;             // every process's default liveness_s
  std::vector<ProcessSpec> processes;  // in start order (dependencies first, then file order)
};

// Builds a LaunchFile from a parsed document (throws config::Error). `file_dir` resolves `root`.
LaunchFile load_launch(const config::Value& root, const std::string& file_dir);
LaunchFile load_launch_file(const std::string& path);

// Replaces ${NAME} in s from vars, else the environment, else an error naming it;
// ${NAME:-default} gives `default` when NAME is unset or empty.
std::string substitute(const std::string& s, const std::map<std::string, std::string>& vars);

// Which processes to run: every autostart one when both lists are empty; else those in one of
// `groups` or named in `names` (autostart or not). Unknown group or name: std::invalid_argument
// naming it.
std::vector<std::size_t> select(const LaunchFile& lf, const std::vector<std::string>& groups,
                                const std::vector<std::string>& names);

}  // namespace tiller::launch
