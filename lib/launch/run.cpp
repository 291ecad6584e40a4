#include "launch/run.hpp"

#include <poll.h>
#include <sys/prctl.h>
#include <sys/signalfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <csignal>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "launch/monitor.hpp"
#include "runtime/live.hpp"
#include "runtime/live_link.hpp"

namespace tiller::launch {

std::string now_stamp() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d-%H%M%S", &tm);
  return buf;
}

namespace {
// "liveness: heartbeats watched from each process's first one: esc, mixer (5 s) (3 s silent: ...)".
std::string liveness_line(const LaunchFile& lf, const std::vector<ProcessSpec>& procs) {
  std::string names;
  for (const auto& p : procs) {
    if (p.liveness_s <= 0) continue;
    char own[48] = "";
    if (p.liveness_s != lf.liveness_s) std::snprintf(own, sizeof own, " (%g s)", p.liveness_s);
    names += (names.empty() ? "" : ", ") + p.name + own;
  }
  if (names.empty()) return "liveness: no process watched (liveness_s: 0)";
  char dflt[32];
  std::snprintf(dflt, sizeof dflt, "%g s", lf.liveness_s);
  return "liveness: heartbeats watched from each process's first one: " + names + " (" + dflt +
         " silent: stopped, then its restart policy)";
}
}  // namespace

int run_plan(const Plan& plan, PosixHost& host, const RunOptions& o) {
  const LaunchFile& lf = plan.lf;
  if (plan.log) {
    std::filesystem::create_directories(std::filesystem::path(plan.log_file).parent_path());
    const std::string manifest = log_stem(plan.log_file) + ".replay.yaml";
    std::ofstream m(manifest);
    write_manifest(m, plan, host);
    if (!m) throw std::runtime_error("cannot write the replay manifest " + manifest);
  }

  // Signals arrive through a signalfd; children get them unblocked before exec.
  sigset_t mask;
  sigemptyset(&mask);
  for (int s : {SIGCHLD, SIGINT, SIGTERM, SIGHUP, SIGUSR1}) sigaddset(&mask, s);
  ::sigprocmask(SIG_BLOCK, &mask, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
  const int sfd = ::signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
  ::prctl(PR_SET_CHILD_SUBREAPER, 1);  // orphaned grandchildren come back to us to be reaped
  {
    std::string guard_error;
    if (host.start_guard(guard_error) < 0)
      host.print("launch", "warning: no guard for grandchildren (" + guard_error +
                               "): if tiller-launch is killed, their children may survive");
  }

  auto note = [&](const std::string& s) { host.print("launch", s); };
  Supervisor sup(plan.procs, lf.ends_with, lf.grace_s, host, note);
  host.print("launch", lf.name + ": " + std::to_string(plan.procs.size()) + " processes, lcm " +
                           lf.lcm_url + (plan.signing.empty() ? "" : ", " + plan.signing));
  for (const auto& h : plan.held_back) host.print("launch", "not started: " + h);
  // Liveness (docs/safety.md, "Stalls and liveness"): the launcher's node hears heartbeats.
  LaunchMonitor monitor(sup);
  std::unique_ptr<LiveLink> link;
  try {
    link = std::make_unique<LiveLink>(lf.lcm_url, o.policy, monitor);
    host.print("launch", liveness_line(lf, plan.procs));
  } catch (const std::exception& e) {
    host.print("launch",
               std::string("warning: ") + e.what() + ": no heartbeat watchdog in this run");
  }
  if (plan.log)
    host.print("launch", "log: " + plan.log_file + log_suffix(lf.logger) + " (replay manifest " +
                             log_stem(plan.log_file) + ".replay.yaml)");
  const TimeUs t0 = wall_time_us();
  sup.start(t0);

  const double every = o.status_every_s;
  TimeUs next_status = every > 0 ? t0 + from_seconds(every) : INT64_MAX;
  TimeUs next_file = t0;
  int interrupts = 0;
  TimeUs drain_until = INT64_MAX;
  TimeUs next_probe = t0;
  for (;;) {
    TimeUs now = wall_time_us();
    if (now >= next_file) {
      std::ofstream(o.status_file)
          << lf.name << " at " << now_stamp() << (sup.stopping() ? " (stopping)" : "") << "\n"
          << sup.status_table(now);
      next_file = now + kUsPerSecond;
    }
    if (now >= next_status) {
      std::cout << sup.status_table(now) << std::flush;
      next_status = now + from_seconds(every);
    }
    if (sup.finished() && drain_until == INT64_MAX) drain_until = now + 200'000;
    const auto fds = host.output_fds();
    if (sup.finished() && (fds.empty() || now >= drain_until)) break;
    TimeUs wake =
        std::min({sup.next_deadline(), next_status, next_file, drain_until, now + kUsPerSecond});
    if (link) wake = std::min(wake, link->next_tick());
    const int timeout_ms = static_cast<int>(std::clamp<TimeUs>((wake - now + 999) / 1000, 0, 1000));
    std::vector<pollfd> pfds{{sfd, POLLIN, 0}};
    for (int fd : fds) pfds.push_back({fd, POLLIN, 0});
    const std::size_t first_out = 1, lcm_at = pfds.size();
    if (link) pfds.push_back({link->fd(), POLLIN, 0});
    ::poll(pfds.data(), pfds.size(), timeout_ms);
    // Heartbeats first: a late loop must not take a process for silent whose heartbeat waits.
    if (link && (pfds[lcm_at].revents & POLLIN)) link->handle();
    now = wall_time_us();
    for (std::size_t k = first_out; k < lcm_at; ++k) {
      if (pfds[k].revents) host.on_readable(pfds[k].fd);
    }
    signalfd_siginfo si{};
    while (::read(sfd, &si, sizeof si) == static_cast<ssize_t>(sizeof si)) {
      const int sig = static_cast<int>(si.ssi_signo);
      if (sig == SIGCHLD) {
        int st = 0;
        pid_t pid;
        while ((pid = ::waitpid(-1, &st, WNOHANG)) > 0) {
          ExitInfo e;
          if (WIFEXITED(st)) e.code = WEXITSTATUS(st);
          if (WIFSIGNALED(st)) e.signal = WTERMSIG(st);
          sup.on_exit(pid, e, now);
        }
      } else if (sig == SIGUSR1) {
        std::cout << sup.status_table(now) << std::flush;
      } else {
        ++interrupts;
        if (interrupts == 1) {
          sup.request_stop(now, std::string("SIG") + sigabbrev_np(sig), kExitOk);
        } else {
          note("second SIG" + std::string(sigabbrev_np(sig)) + ": SIGKILL to everything");
          for (const auto& p : sup.processes()) host.signal(p.pid, SIGKILL);
        }
      }
    }
    sup.poll(now);
    monitor.after_poll(now);
    // Until lcm-logger has written, a heartbeat every 50 ms gives it something to write.
    if (link && sup.waiting_for_file() && now >= next_probe) {
      monitor.publish_heartbeat_now(now);
      next_probe = now + 50'000;
    }
    if (link) link->tick(now);
  }
  const TimeUs end = wall_time_us();
  std::cout << sup.status_table(end);
  std::ofstream(o.status_file) << lf.name << " finished at " << now_stamp() << ": "
                               << sup.stop_reason() << "\n"
                               << sup.status_table(end);
  if (plan.log) {
    std::cout << "tiller-launch: log " << plan.log_file << log_suffix(lf.logger)
              << (lf.logger.split_mb > 0
                      ? (lf.logger.rotate > 0 ? " (the newest part; older: .1, .2, ...)"
                                              : " (and following parts)")
                      : "")
              << "\n";
  }
  std::cout << "tiller-launch: " << sup.stop_reason() << "; exit status " << sup.exit_status()
            << "\n";
  return sup.exit_status();
}

}  // namespace tiller::launch
