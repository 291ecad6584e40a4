// A launch plan: what tiller-launch starts for a launch file and its command-line choices
// (which groups or processes, the log file, the LCM URL), before anything is started. Pure
// logic: the date-time of a new log's name is an argument; nothing forks or reads a clock.
// Also what the plan writes besides starting processes: the replay manifest next to the log
// (LOG.replay.yaml, read by tiller-replay) and the --check printout.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "launch/launch_file.hpp"
#include "launch/posix_host.hpp"

namespace tiller::launch {

// The command line's choices (tiller-launch --group, --only, --no-log, --log-dir, --log-file,
// --lcm-url).
struct LaunchChoices {
  std::vector<std::string> groups, only;  // empty: every autostart process
  bool no_log = false;
  std::string log_dir;   // empty: the launch file's logger.dir (relative: to its root)
  std::string log_file;  // empty: <log dir>/<stamp>.lcmlog, or <log dir>/<name>.lcmlog with rotate
  std::optional<std::string> lcm_url;  // given: replaces the launch file's (TTL 0 unless given)
};

struct Plan {
  LaunchFile lf;                       // with the chosen LCM URL
  std::vector<ProcessSpec> procs;      // in start order: lcm-logger first when logging
  std::vector<std::string> held_back;  // "name (autostart: false; start it with ...)"
  bool log = false;
  std::string log_file;  // absolute when given relative; what lcm-logger is told
  std::string signing;   // "signing: key FILE, ..." (launch/signing.hpp), printed with the plan
};

// Throws std::invalid_argument for an unknown group or process name (exit 2). `stamp` names a
// new log ("2026-01-31-120000"); `cwd` makes a relative --log-file absolute.
Plan make_plan(LaunchFile lf, const LaunchChoices& c, const std::string& stamp,
               const std::string& cwd);

// What lcm-logger appends to the file name: .0 with rotate (the newest), .00 with split parts.
std::string log_suffix(const LoggerSpec& l);
// One log per launch with rotate: lcm-logger 1.4 --rotate only rotates when it splits, so a new
// launch would reopen the last run's FILE.0. Before the logger starts, this moves FILE.k to
// FILE.(k+1) for k = rotate-2 .. 0 (FILE.(rotate-1), the oldest, is removed), so the run starts
// a new FILE.0 and the bound stays `rotate` files. Returns one line per file it could not move
// (empty: all went). Not called by --check, which creates, moves and removes nothing.
std::string rotate_previous_logs(const std::string& log_file, int rotate);
// The log's name without .lcmlog (the manifest is <stem>.replay.yaml).
std::string log_stem(const std::string& log_file);
// $XDG_RUNTIME_DIR (else /tmp) + /tiller-launch-<name>.status; `runtime_dir` may be empty.
std::string default_status_file(const std::string& launch_name, const std::string& runtime_dir);

// The replay manifest of a run: what each process ran with (after ${...} substitution).
void write_manifest(std::ostream& m, const Plan& plan, const PosixHost& host);
// The --check printout: the plan, each process's resolved command line and restart policy.
void print_check(std::ostream& out, const Plan& plan, const PosixHost& host);
// Every process's program exists (next to tiller-launch or on PATH) and its ${...} resolve;
// else one line per problem naming the launch file's line, and false.
bool check_programs(const Plan& plan, const PosixHost& host, std::ostream& err);

}  // namespace tiller::launch
