// The launcher's own node, "launch" (heartbeat TILLER_HEARTBEAT_LAUNCH): hears the heartbeat
// of every process the launch watches (liveness_s > 0) and tells the Supervisor, and reports
// the liveness watchdog in its own heartbeat, so a run's log shows it:
//   state   OK, or DEGRADED while a process is silent, restarting or given up on;
//   status  the launcher's line about the last process stopped for a silent heartbeat
//           ("mixer: no heartbeat for 3.0 s (liveness_s 3): treated as failed, ..."), else
//           "N processes watched";
//   counters  watchdog.silent.<process> (times stopped for a silent heartbeat),
//           restarts.<process> (for the first kNamedProcesses), and rejected.heartbeat.invalid (a
//           heartbeat that fails checks::check) / rejected.heartbeat.unknown (a node no process
//           watches).
// It also hears its own heartbeat come back, which tells the Supervisor that the bus works
// (Supervisor::on_bus: no process is judged silent while the launcher hears nothing at all).
// With a signing key each watched channel accepts only its own node as the sender, so a
// process cannot keep another one "alive". Pure (Node rules): heartbeats and time in.
#pragma once

#include <cstdint>
#include <vector>

#include <tiller/heartbeat_t.hpp>

#include "launch/supervisor.hpp"
#include "runtime/node.hpp"

namespace tiller::launch {

class LaunchMonitor : public Node {
 public:
  static constexpr TimeUs kTickUs = 1'000'000;        // the heartbeat's rate
  static constexpr std::size_t kNamedProcesses = 24;  // processes with their own counters
  explicit LaunchMonitor(Supervisor& sup);
  // Call after each Supervisor::poll: a new silent-heartbeat stop is published at once (the
  // log has it then, not at the next whole second).
  void after_poll(TimeUs now);

 protected:
  void on_tick(TimeUs now) override;

 private:
  void on_heartbeat(const heartbeat_t& m, TimeUs now);
  void refresh();

  Supervisor& sup_;
  std::vector<std::int64_t*> silent_, restarts_;  // per process, in the supervisor's order
  std::int64_t* invalid_ = nullptr;
  std::int64_t* unknown_ = nullptr;
  std::int64_t spare_ = 0;  // the counters of processes past kNamedProcesses
  int watched_ = 0;
  int silent_seen_ = 0;
};

}  // namespace tiller::launch
