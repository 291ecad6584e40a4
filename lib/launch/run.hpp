// Runs a launch plan on the wall clock: the supervisor (launch/supervisor.hpp) over a PosixHost,
// signals through a signalfd (SIGINT/SIGTERM/SIGHUP stop the run in reverse order, a second one
// SIGKILLs everything; SIGUSR1 prints the status table), the children's output prefixed with
// their names, the status table kept in a file, the replay manifest written next to the log.
// The launcher's own node (launch/monitor.hpp) hears the watched processes' heartbeats over LCM
// (runtime/live_link.hpp) and publishes TILLER_HEARTBEAT_LAUNCH.
// This is tiller-launch's event loop; the decisions are the Supervisor's (tested without fork).
#pragma once

#include <string>

#include "auth/verifier.hpp"
#include "launch/plan.hpp"

namespace tiller::launch {

struct RunOptions {
  double status_every_s = 0;  // print the status table this often (0: only at the end, SIGUSR1)
  std::string status_file;    // kept up to date (once a second) and written at the end
  auth::Policy policy;        // the launch's signing: heartbeats checked, its own one signed
};

// The local date and time now, "2026-01-31-120000" (a new log's name, the status file's header).
std::string now_stamp();

// Starts plan.procs and supervises them until the run ends; returns the exit status
// (kExitOk, kExitRunFailed, kExitCriticalFailed). Throws when the manifest cannot be written.
int run_plan(const Plan& plan, PosixHost& host, const RunOptions& o);

}  // namespace tiller::launch
