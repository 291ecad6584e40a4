#include "runtime/realtime.hpp"

#include <malloc.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

namespace tiller::realtime {

namespace {

// Capability numbers (linux/capability.h).
constexpr int kCapIpcLock = 14;
constexpr int kCapSysNice = 23;

std::uint64_t soft_limit(int resource) {
  rlimit rl{};
  if (::getrlimit(resource, &rl) != 0) return 0;
  return rl.rlim_cur == RLIM_INFINITY ? Limits::kInfinity : static_cast<std::uint64_t>(rl.rlim_cur);
}

std::uint64_t effective_caps() {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("CapEff:", 0) == 0) return std::stoull(line.substr(7), nullptr, 16);
  }
  return 0;
}

// The initial user namespace maps every uid to itself: "0 0 4294967295".
bool in_user_namespace() {
  std::ifstream in("/proc/self/uid_map");
  std::uint64_t inside = 1, outside = 1, count = 0;
  if (!(in >> inside >> outside >> count)) return false;
  return !(inside == 0 && outside == 0 && count == 4294967295ULL);
}

class Os : public System {
 public:
  Limits limits() override {
    Limits l;
    l.rtprio = soft_limit(RLIMIT_RTPRIO);
    l.memlock = soft_limit(RLIMIT_MEMLOCK);
    const std::uint64_t caps = effective_caps();
    l.cap_sys_nice = (caps >> kCapSysNice) & 1U;
    l.cap_ipc_lock = (caps >> kCapIpcLock) & 1U;
    l.user_namespace = in_user_namespace();
    return l;
  }
  int set_fifo(int priority) override {
    sched_param sp{};
    sp.sched_priority = priority;
    return ::sched_setscheduler(0, SCHED_FIFO, &sp) == 0 ? 0 : errno;
  }
  int lock_all() override {
    if (::mlockall(MCL_CURRENT | MCL_FUTURE) != 0) return errno;
    // Freed memory stays with the process (locked) instead of going back to the kernel, and
    // large blocks come from the locked heap rather than new mappings.
    ::mallopt(M_TRIM_THRESHOLD, -1);
    ::mallopt(M_MMAP_MAX, 0);
    prefault_stack();
    return 0;
  }

 private:
  // Touches 256 KiB of stack now, so that deeper calls later do not fault it in.
  static void prefault_stack() {
    volatile unsigned char stack[256 * 1024];
    for (std::size_t i = 0; i < sizeof stack; i += 4096) stack[i] = 0;
  }
};

std::string errno_name(int e) {
  switch (e) {
    case EPERM:
      return "EPERM";
    case ENOMEM:
      return "ENOMEM";
    case EAGAIN:
      return "EAGAIN";
    case EINVAL:
      return "EINVAL";
    default:
      return "errno " + std::to_string(e);
  }
}

std::string bytes(std::uint64_t b) {
  if (b == Limits::kInfinity) return "unlimited";
  if (b >= 1024 * 1024 && b % (1024 * 1024) == 0) return std::to_string(b >> 20) + " MiB";
  if (b >= 1024 && b % 1024 == 0) return std::to_string(b >> 10) + " KiB";
  return std::to_string(b) + " bytes";
}

// Said when the process is in a user namespace: its capabilities count only inside it.
std::string in_namespace(const Limits& l) {
  return l.user_namespace
             ? " (it runs in a user namespace: unshare -r, tools/netns-run or a rootless "
               "container, whose root has no capability on the host; run it as real root, e.g. "
               "unshare -n without -r, or outside the namespace)"
             : "";
}

std::string fifo_problem(int priority, int e, const Limits& l) {
  const std::string p = std::to_string(priority);
  std::string s = "SCHED_FIFO priority " + p + " refused (" + errno_name(e) + "): ";
  if (e != EPERM) return s + std::strerror(e);
  if (!l.cap_sys_nice && l.rtprio < static_cast<std::uint64_t>(priority)) {
    return s + "it needs CAP_SYS_NICE or RLIMIT_RTPRIO >= " + p +
           ", and this process has no CAP_SYS_NICE" + in_namespace(l) + " and RLIMIT_RTPRIO " +
           std::to_string(l.rtprio) + "; grant it with LimitRTPRIO=" + p +
           " in the systemd unit (tools/systemd/tiller@.service has it), '<user> - rtprio " + p +
           "' in /etc/security/limits.d/tiller.conf (then log in again), or run as root";
  }
  return s + "refused although " +
         (l.cap_sys_nice ? std::string("CAP_SYS_NICE is held")
                         : "RLIMIT_RTPRIO is " + std::to_string(l.rtprio)) +
         ": the process's cgroup has no real-time runtime (a kernel with CONFIG_RT_GROUP_SCHED "
         "and cpu.rt_runtime_us = 0); give its cgroup a share or start it outside";
}

std::string lock_problem(std::optional<int> e, const Limits& l) {
  if (!e) {
    return "memory not locked: it needs CAP_IPC_LOCK or RLIMIT_MEMLOCK = unlimited, and this "
           "process has no CAP_IPC_LOCK" +
           in_namespace(l) + " and RLIMIT_MEMLOCK " + bytes(l.memlock) +
           " (with MCL_FUTURE every allocation past a finite limit would fail, so Tiller does "
           "not try); grant LimitMEMLOCK=infinity in the systemd unit "
           "(tools/systemd/tiller@.service has it), '<user> - memlock unlimited' in "
           "/etc/security/limits.d/tiller.conf, or run as root";
  }
  return "memory not locked: mlockall refused (" + errno_name(*e) + "): " + std::strerror(*e) +
         " (RLIMIT_MEMLOCK " + bytes(l.memlock) + ", CAP_IPC_LOCK " +
         (l.cap_ipc_lock ? "held" : "not held") + ")";
}

std::optional<Report> g_report;

}  // namespace

System& os() {
  static Os s;
  return s;
}

Report apply(const Request& r, System& sys) {
  Report rep;
  rep.request = r;
  if (!r.any()) return rep;
  Limits l = sys.limits();
  if (l.user_namespace) l.cap_sys_nice = l.cap_ipc_lock = false;  // they count only on the host
  if (r.lock_memory) {
    // Locked first, so the pages the scheduler change touches are already resident.
    if (!l.cap_ipc_lock && l.memlock != Limits::kInfinity) {
      rep.problems.push_back(lock_problem(std::nullopt, l));
    } else if (const int e = sys.lock_all(); e != 0) {
      rep.problems.push_back(lock_problem(e, l));
    } else {
      rep.locked = true;
    }
  }
  if (r.priority > 0) {
    if (const int e = sys.set_fifo(r.priority); e != 0) {
      rep.problems.push_back(fifo_problem(r.priority, e, l));
    } else {
      rep.priority = r.priority;
    }
  }
  return rep;
}

std::string summary(const Report& rep) {
  std::ostringstream s;
  if (rep.priority > 0)
    s << "SCHED_FIFO priority " << rep.priority;
  else
    s << "normal scheduler";
  s << (rep.locked ? ", memory locked" : ", memory not locked");
  return s.str();
}

const Report* process_report() {
  return g_report ? &*g_report : nullptr;
}

void set_process_report(const Report& rep) {
  g_report = rep;
}

}  // namespace tiller::realtime
