// Process supervision logic of tiller-launch, without fork: a state machine told when
// processes exit and what time it is, which asks a ProcessHost to start and signal them.
// Starts processes in order (each after its start_delay_s), restarts per policy with
// exponential back-off and a limit, ends the run when the `ends_with` process exits, when a
// critical process is given up on, when nothing is left to run, or on request (Ctrl-C,
// SIGTERM); then stops everything in reverse start order: SIGTERM, SIGKILL after the grace
// period, one process at a time. Liveness: told each heartbeat a process publishes
// (on_heartbeat), it treats a process whose heartbeat has been silent for its liveness_s as
// failed: SIGTERM and SIGCONT (a SIGSTOPped process cannot act on SIGTERM until continued),
// SIGKILL after the grace period, then its restart policy as for a failed exit. A process is
// watched from its first heartbeat after each start, so one that publishes none (lcm-logger, a
// shell script) is never stopped for it. Times in us (core/time.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/time.hpp"
#include "launch/launch_file.hpp"

namespace tiller::launch {

// Exit statuses of tiller-launch.
inline constexpr int kExitOk = 0;              // run ended cleanly (or stopped on request)
inline constexpr int kExitRunFailed = 1;       // the ends_with process, or a process, failed
inline constexpr int kExitUsage = 2;           // bad launch file or command line
inline constexpr int kExitCriticalFailed = 3;  // a critical process was given up on

struct ExitInfo {
  int code = 0;         // exit code when it exited
  int signal = 0;       // signal that killed it, 0 if it exited
  double silent_s = 0;  // > 0: stopped by the launcher after its heartbeat was silent this long
  bool failed() const { return code != 0 || signal != 0 || silent_s > 0; }
  // "exit 0", "exit 3", "killed by SIGKILL", "heartbeat silent 3.0 s, then exit 0"
  std::string describe() const;
};

class ProcessHost {
 public:
  virtual ~ProcessHost() = default;
  // Starts the process; returns its pid (> 0), or -1 and sets `error`.
  virtual int spawn(const ProcessSpec& p, std::string& error) = 0;
  // Sends `sig` to the process and its process group.
  virtual void signal(int pid, int sig) = 0;
  // True when `path` exists, is not empty and was written at or after `since` (wall clock, us):
  // ProcessSpec::start_after_file (an old log of the same name, e.g. rotate's FILE.0 before
  // lcm-logger renames it, does not count). A host without files: always true.
  virtual bool file_has_data(const std::string& path, TimeUs since) {
    (void)path;
    (void)since;
    return true;
  }
};

// kSilent: being stopped because its heartbeat went silent ("silent" in the table).
enum class State {
  kPending,
  kRunning,
  kBackoff,
  kStopping,
  kExited,
  kGaveUp,
  kNotStarted,
  kSilent
};
const char* to_string(State s);

struct ProcStatus {
  ProcessSpec spec;
  State state = State::kPending;
  int pid = -1;
  int restarts = 0;  // total restarts in this run
  int streak = 0;    // restarts since it last ran stable_after_s
  bool has_exited = false;
  ExitInfo last_exit;
  TimeUs started_at = 0;
  TimeUs restart_at = 0;
  TimeUs kill_at = 0;
  bool killed = false;  // needed SIGKILL when stopping
  bool heard = false;   // a heartbeat came since the last start (so it is watched)
  TimeUs last_heartbeat = 0;
  double silent_s = 0;   // > 0: being stopped (kSilent) after this long without a heartbeat
  int silent_stops = 0;  // times stopped for a silent heartbeat in this run
};

class Supervisor {
 public:
  using Note = std::function<void(const std::string&)>;
  Supervisor(std::vector<ProcessSpec> procs, std::string ends_with, double grace_s,
             ProcessHost& host, Note note = {});

  void start(TimeUs now);
  // A child exited (unknown pids are ignored).
  void on_exit(int pid, ExitInfo e, TimeUs now);
  // Begins the orderly stop (idempotent; the first reason and status win).
  void request_stop(TimeUs now, const std::string& reason, int status = kExitOk);
  // A heartbeat of node `node` (heartbeat_t.process) arrived at `now`: the running process
  // whose heartbeat_node() it is counts as alive. False when no process watches that node.
  bool on_heartbeat(std::string_view node, TimeUs now);
  // The launcher heard its own heartbeat (1 Hz) come back over LCM at `now`: the bus works.
  // Once told this, a process's silence counts only while the bus is known to work (up to
  // kBusEchoUs after the last echo), and from when the bus came back after a gap: a link or
  // route that goes down (no multicast route, so no local loopback either) must not make every
  // process look silent.
  void on_bus(TimeUs now);
  static constexpr TimeUs kBusEchoUs = 1'200'000;
  // Runs what is due at `now`: starts, restarts, silent heartbeats, SIGKILL escalation.
  void poll(TimeUs now);

  bool stopping() const { return stopping_; }
  bool finished() const { return finished_; }
  int exit_status() const { return status_; }
  const std::string& stop_reason() const { return reason_; }
  // Earliest time poll() has something to do (INT64_MAX: nothing scheduled).
  TimeUs next_deadline() const;
  // True while the next start waits for its start_after_file (the launcher then publishes its
  // heartbeat often, so that lcm-logger has something to write).
  bool waiting_for_file() const { return waiting_file_; }
  const std::vector<ProcStatus>& processes() const { return procs_; }
  // A table: name, group, state, pid, up_s, hb_s (since its last heartbeat), restarts, last exit.
  std::string status_table(TimeUs now) const;
  // Processes stopped for a silent heartbeat so far, and the launcher's line about the last.
  int silent_stops() const { return silent_stops_; }
  const std::string& last_silent() const { return last_silent_; }

 private:
  void spawn(std::size_t i, TimeUs now);
  void handle_exit(std::size_t i, ExitInfo e, TimeUs now);
  void advance_stop(TimeUs now);
  void check_all_done(TimeUs now);
  void check_liveness(TimeUs now);
  void say(const std::string& s) {
    if (note_) note_(s);
  }

  std::vector<ProcStatus> procs_;
  std::string ends_with_;
  TimeUs grace_us_;
  ProcessHost& host_;
  Note note_;
  std::size_t next_start_ = 0;
  TimeUs start_due_ = 0;
  bool waiting_file_ = false;
  TimeUs last_poll_ = 0;
  TimeUs started_at_ = 0;
  bool started_ = false;
  bool stopping_ = false;
  bool finished_ = false;
  int stop_index_ = -1;  // process being stopped (reverse order)
  int status_ = kExitOk;
  std::string reason_;
  int silent_stops_ = 0;
  std::string last_silent_;
  TimeUs last_bus_ = -1;  // -1: never told (no bus gate, as in tests without one)
  TimeUs bus_back_ = 0;
  TimeUs last_check_ = 0;  // last check_liveness (a deadline is never earlier than +100 ms)
};

}  // namespace tiller::launch
