// What tiller-replay replays, decided before anything runs: which processes of a log, each with
// its config and recorded arguments, and the tolerances, from the command line's choices and
// the log's replay manifest (LOG.replay.yaml; format in apps/replay/main.cpp). Without a
// manifest, the replayable processes whose heartbeat is in the log. Relative config paths
// resolve against the manifest's root, else as app::resolve_path does. A usage or manifest
// error throws (std::runtime_error, config::Error): tiller-replay prints it and exits 2.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "replaytool/compare.hpp"
#include "runtime/event.hpp"

namespace tiller::replaytool {

// The command line's choices (tiller-replay's options; unset: the manifest's, else the default).
struct ReplayRequest {
  std::string log_path;
  std::string process = "all";        // a replayable process's name, or all
  std::string manifest;               // --configs; empty: LOG.replay.yaml when it exists
  std::optional<std::string> config;  // --config FILE (needs one --process)
  bool live = false, heartbeats = false;
  std::optional<double> tolerance, time_tolerance_ms, relative_tolerance, live_match;
  std::size_t show = 1;
};

struct Planned {
  const ProcessEntry* entry = nullptr;
  std::string config;             // as given (manifest, --config or the default)
  std::vector<std::string> args;  // recorded arguments, paths resolved
};

struct ReplayPlan {
  std::string process, log_path;  // as requested
  std::vector<Planned> processes;
  std::vector<std::string> skipped;  // "name (why)"
  Tolerance tol;
  bool live = false, heartbeats = false;
  bool from_manifest = false;  // the manifest listed the processes
  std::string manifest;        // the one read, or empty
  std::string root;            // the manifest's root, or empty
  std::string resolve(const std::string& path) const;
};

// The replayable process called `name`, or nullptr.
const ProcessEntry* replayable(const std::string& name);
// "mixer, esc, ..." (for messages).
std::string replayable_names();

// Step 1, before the log is read: checks the request, reads the manifest (its processes when it
// lists them), sets the tolerances.
ReplayPlan plan_from_manifest(const ReplayRequest& req);
// Step 2, with the log: without a manifest, the replayable processes that ran (their heartbeat
// is in the log) and, as skipped, those that ran but cannot be replayed; applies --config; drops
// (process all) or refuses (one process) a process without a config.
void plan_from_log(ReplayPlan& plan, const ReplayRequest& req, const std::vector<Event>& log);

// Prints the skipped processes; throws when nothing is left to replay. Then replays every
// planned process and prints each report, then the verdict line
// ("tiller-replay: PASS (2 processes checked: mixer, esc; tolerance 0, ...)"). True: all match.
bool run_plan(const ReplayPlan& plan, const std::vector<Event>& log, std::size_t show,
              std::ostream& out);

}  // namespace tiller::replaytool
