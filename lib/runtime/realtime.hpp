// Real-time scheduling and locked memory for a whole process (docs/operations.md, "Real time").
// A program asks for it on its command line (runtime/app.hpp):
//   --realtime-priority N   SCHED_FIFO at priority N (1..99) for the process
//   --lock-memory           mlockall(MCL_CURRENT | MCL_FUTURE): no page fault on the hot path
//   --realtime-required     refused -> the program does not start (exit 2)
// tiller-launch passes these from a process's `realtime:` entry in the launch file, so a
// program started by hand or by systemd directly behaves the same way.
//
// The process applies it itself, at start-up, before it opens devices or LCM. When the system
// does not permit it, apply() names what is missing and how to grant it:
//   SCHED_FIFO needs CAP_SYS_NICE or RLIMIT_RTPRIO >= N (systemd LimitRTPRIO=N, limits.conf
//     rtprio); never granted inside a user namespace (unshare -r, tools/netns-run, a rootless
//     container), whose root has no CAP_SYS_NICE on the host;
//   locking needs CAP_IPC_LOCK or RLIMIT_MEMLOCK = infinity (systemd LimitMEMLOCK=infinity,
//     limits.conf memlock unlimited). A finite limit is not tried: with MCL_FUTURE every later
//     allocation past it would fail, which is worse than not locking.
// Not permitted and not required: one warning line per refusal on stderr, the program runs on
// the normal scheduler, and its heartbeat says so (counters realtime.refused = 1,
// realtime.priority, realtime.locked: see LiveExecutor::add).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tiller::realtime {

struct Request {
  int priority = 0;          // SCHED_FIFO priority 1..99; 0: the normal scheduler
  bool lock_memory = false;  // mlockall(MCL_CURRENT | MCL_FUTURE)
  bool required = false;     // not permitted -> refuse to start
  bool any() const { return priority > 0 || lock_memory; }
};

// What the process may do, as the kernel tells it.
struct Limits {
  static constexpr std::uint64_t kInfinity = UINT64_MAX;
  std::uint64_t rtprio = 0;   // soft RLIMIT_RTPRIO
  std::uint64_t memlock = 0;  // soft RLIMIT_MEMLOCK, bytes (kInfinity: unlimited)
  bool cap_sys_nice = false;  // in the effective set
  bool cap_ipc_lock = false;
  bool user_namespace = false;  // not the initial user namespace (uid_map is not the identity)
};

// The system calls, behind an interface so that tests can refuse them (a fake) as well as run
// them for real.
class System {
 public:
  virtual ~System() = default;
  virtual Limits limits() = 0;
  virtual int set_fifo(int priority) = 0;  // sched_setscheduler(0, SCHED_FIFO): 0 or errno
  virtual int lock_all() = 0;              // mlockall(MCL_CURRENT | MCL_FUTURE): 0 or errno
};
System& os();  // the real one

struct Report {
  Request request;
  int priority = 0;     // the SCHED_FIFO priority in force (0: not real-time)
  bool locked = false;  // memory locked
  // One line per refusal: what, the errno, what is missing and how to grant it.
  std::vector<std::string> problems;
  bool granted() const { return problems.empty(); }
};

// Applies `r` (nothing to do when !r.any()). Never throws; refusals go in the report.
Report apply(const Request& r, System& sys);

// "SCHED_FIFO priority 80, memory locked" (what is in force), for the start-up line.
std::string summary(const Report& rep);

// The process's report, set once by app::parse when the command line asked for real time;
// nullptr when it did not. The scheduling policy belongs to the process, hence one global.
const Report* process_report();
void set_process_report(const Report& rep);

}  // namespace tiller::realtime
