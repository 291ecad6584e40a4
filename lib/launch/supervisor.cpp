#include "launch/supervisor.hpp"

#include <algorithm>
#include <climits>
#include <csignal>
#include <cstring>
#include <sstream>

namespace tiller::launch {

namespace {
std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f s", s);
  return b;
}
}  // namespace

std::string ExitInfo::describe() const {
  std::string how;
  if (signal != 0) {
    const char* n = sigabbrev_np(signal);
    how = std::string("killed by SIG") + (n ? n : std::to_string(signal).c_str());
  } else {
    how = "exit " + std::to_string(code);
  }
  return silent_s > 0 ? "heartbeat silent " + seconds(silent_s) + ", then " + how : how;
}

const char* to_string(State s) {
  switch (s) {
    case State::kPending:
      return "pending";
    case State::kRunning:
      return "running";
    case State::kBackoff:
      return "restarting";
    case State::kStopping:
      return "stopping";
    case State::kExited:
      return "exited";
    case State::kGaveUp:
      return "gave-up";
    case State::kNotStarted:
      return "not-started";
    case State::kSilent:
      return "silent";
  }
  return "?";
}

Supervisor::Supervisor(std::vector<ProcessSpec> procs, std::string ends_with, double grace_s,
                       ProcessHost& host, Note note)
    : ends_with_(std::move(ends_with)),
      grace_us_(from_seconds(grace_s)),
      host_(host),
      note_(std::move(note)) {
  for (auto& p : procs) {
    ProcStatus s;
    s.spec = std::move(p);
    procs_.push_back(std::move(s));
  }
}

void Supervisor::start(TimeUs now) {
  started_ = true;
  started_at_ = now;
  next_start_ = 0;
  start_due_ = procs_.empty() ? now : now + from_seconds(procs_[0].spec.start_delay_s);
  poll(now);
  check_all_done(now);
}

void Supervisor::spawn(std::size_t i, TimeUs now) {
  auto& p = procs_[i];
  std::string error;
  const int pid = host_.spawn(p.spec, error);
  p.started_at = now;
  p.heard = false;
  p.silent_s = 0;
  p.killed = false;
  if (pid <= 0) {
    say(p.spec.name + ": cannot start: " + error);
    p.pid = -1;
    p.state = State::kRunning;  // so that handle_exit applies the policy
    handle_exit(i, ExitInfo{127, 0}, now);
    return;
  }
  p.pid = pid;
  p.state = State::kRunning;
}

void Supervisor::poll(TimeUs now) {
  if (!started_ || finished_) return;
  waiting_file_ = false;
  if (!stopping_) {
    last_poll_ = now;
    while (next_start_ < procs_.size() && now >= start_due_) {
      const ProcessSpec& next = procs_[next_start_].spec;
      if (!next.start_after_file.empty() &&
          !host_.file_has_data(next.start_after_file, started_at_)) {
        if (now < start_due_ + from_seconds(next.start_after_file_max_s)) {
          waiting_file_ = true;
          break;
        }
        say("warning: " + next.start_after_file + " is still empty after " +
            std::to_string(static_cast<int>(next.start_after_file_max_s)) + " s: starting " +
            next.name + " anyway (what comes before the logger's first write is not in the log)");
      }
      say("starting " + procs_[next_start_].spec.name);
      spawn(next_start_, now);
      ++next_start_;
      if (stopping_) break;
      if (next_start_ < procs_.size())
        start_due_ = now + from_seconds(procs_[next_start_].spec.start_delay_s);
    }
    for (std::size_t i = 0; i < procs_.size() && !stopping_; ++i) {
      auto& p = procs_[i];
      if (p.state == State::kBackoff && now >= p.restart_at) {
        say("restarting " + p.spec.name + " (restart " + std::to_string(p.restarts) + ")");
        spawn(i, now);
      }
    }
    if (!stopping_) check_liveness(now);
  }
  for (auto& p : procs_) {
    if (p.state == State::kSilent && now >= p.kill_at) {
      say(p.spec.name + ": still running after the grace period, SIGKILL");
      host_.signal(p.pid, SIGKILL);
      p.killed = true;
      p.kill_at = now + grace_us_;
    }
  }
  if (stopping_) advance_stop(now);
}

bool Supervisor::on_heartbeat(std::string_view node, TimeUs now) {
  for (auto& p : procs_) {
    if (p.spec.liveness_s <= 0 || p.spec.heartbeat_node() != node) continue;
    if (p.state == State::kRunning) {
      p.heard = true;
      p.last_heartbeat = now;
    }
    return true;  // a process being stopped or restarted may still say one
  }
  return false;
}

void Supervisor::on_bus(TimeUs now) {
  if (last_bus_ < 0 || now - last_bus_ > kBusEchoUs) bus_back_ = now;
  last_bus_ = now;
}

void Supervisor::check_liveness(TimeUs now) {
  last_check_ = now;
  // Silence counts only while the bus is known to work.
  const TimeUs heard_until = last_bus_ < 0 ? now : std::min(now, last_bus_ + kBusEchoUs);
  for (auto& p : procs_) {
    if (p.state != State::kRunning || !p.heard || p.spec.liveness_s <= 0) continue;
    const TimeUs silent = heard_until - std::max(p.last_heartbeat, bus_back_);
    if (silent < from_seconds(p.spec.liveness_s)) continue;
    p.silent_s = to_seconds(silent);
    ++p.silent_stops;
    ++silent_stops_;
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", p.spec.liveness_s);
    last_silent_ = p.spec.name + ": no heartbeat for " + seconds(p.silent_s) + " (liveness_s " +
                   limit +
                   "): treated as failed, stopping it (SIGTERM and SIGCONT, SIGKILL after " +
                   seconds(to_seconds(grace_us_)) + ")";
    say(last_silent_);
    // SIGTERM first: a stopped process has it pending when SIGCONT wakes it, so it shuts down
    // (ESCs to neutral) before it acts on anything that queued up meanwhile.
    host_.signal(p.pid, SIGTERM);
    host_.signal(p.pid, SIGCONT);
    p.state = State::kSilent;
    p.kill_at = now + grace_us_;
  }
}

void Supervisor::on_exit(int pid, ExitInfo e, TimeUs now) {
  for (std::size_t i = 0; i < procs_.size(); ++i) {
    if (procs_[i].pid == pid && pid > 0) {
      handle_exit(i, e, now);
      return;
    }
  }
}

void Supervisor::handle_exit(std::size_t i, ExitInfo e, TimeUs now) {
  auto& p = procs_[i];
  p.pid = -1;
  p.has_exited = true;
  e.silent_s = p.silent_s;  // stopped for a silent heartbeat: a failure, whatever its status
  p.silent_s = 0;
  p.last_exit = e;
  if (stopping_) {
    p.state = State::kExited;
    say(p.spec.name + " stopped (" + e.describe() + (p.killed ? ", needed SIGKILL" : "") + ")");
    advance_stop(now);
    return;
  }
  say(p.spec.name + " exited (" + e.describe() + ")");
  if (p.spec.name == ends_with_) {
    p.state = State::kExited;
    request_stop(now, "the run ended: " + p.spec.name + " " + e.describe(),
                 e.failed() ? kExitRunFailed : kExitOk);
    return;
  }
  if (now - p.started_at >= from_seconds(p.spec.stable_after_s)) p.streak = 0;
  const bool again =
      p.spec.restart == Restart::kAlways || (p.spec.restart == Restart::kOnFailure && e.failed());
  if (!again) {
    p.state = State::kExited;
    if (e.failed() && p.spec.critical) {
      request_stop(now, "critical process " + p.spec.name + " failed (" + e.describe() + ")",
                   kExitCriticalFailed);
      return;
    }
    check_all_done(now);
    return;
  }
  if (p.streak >= p.spec.max_restarts) {
    p.state = State::kGaveUp;
    say(p.spec.name + ": giving up after " + std::to_string(p.streak) + " restarts");
    if (p.spec.critical) {
      request_stop(now, "critical process " + p.spec.name + " given up on", kExitCriticalFailed);
      return;
    }
    check_all_done(now);
    return;
  }
  double delay = p.spec.backoff_s;
  for (int k = 0; k < p.streak && delay < p.spec.backoff_max_s; ++k) delay *= 2.0;
  delay = std::min(delay, p.spec.backoff_max_s);
  ++p.streak;
  ++p.restarts;
  p.state = State::kBackoff;
  p.restart_at = now + from_seconds(delay);
}

void Supervisor::check_all_done(TimeUs now) {
  if (stopping_ || next_start_ < procs_.size()) return;
  bool any_failed = false;
  for (const auto& p : procs_) {
    if (p.state == State::kRunning || p.state == State::kBackoff || p.state == State::kPending ||
        p.state == State::kSilent)
      return;
    if (p.state == State::kGaveUp || (p.has_exited && p.last_exit.failed())) any_failed = true;
  }
  request_stop(now, "no process left running", any_failed ? kExitRunFailed : kExitOk);
}

void Supervisor::request_stop(TimeUs now, const std::string& reason, int status) {
  if (stopping_ || finished_) return;
  stopping_ = true;
  reason_ = reason;
  status_ = status;
  say("stopping: " + reason);
  for (auto& p : procs_) {
    if (p.state == State::kPending) p.state = State::kNotStarted;
  }
  stop_index_ = static_cast<int>(std::min(next_start_, procs_.size())) - 1;
  advance_stop(now);
}

void Supervisor::advance_stop(TimeUs now) {
  while (stop_index_ >= 0) {
    auto& p = procs_[static_cast<std::size_t>(stop_index_)];
    if (p.state == State::kBackoff) p.state = State::kExited;
    if (p.state == State::kSilent) p.state = State::kStopping;  // already signalled
    if (p.state == State::kRunning) {
      host_.signal(p.pid, SIGTERM);
      p.state = State::kStopping;
      p.kill_at = now + grace_us_;
      return;
    }
    if (p.state == State::kStopping) {
      if (now >= p.kill_at) {
        say(p.spec.name + ": still running after the grace period, SIGKILL");
        host_.signal(p.pid, SIGKILL);
        p.killed = true;
        p.kill_at = now + grace_us_;
      }
      return;
    }
    --stop_index_;
  }
  finished_ = true;
}

TimeUs Supervisor::next_deadline() const {
  TimeUs t = INT64_MAX;
  if (!started_ || finished_) return t;
  if (!stopping_) {
    if (next_start_ < procs_.size())
      t = std::min(t, waiting_file_ ? std::max(start_due_, last_poll_ + 20'000) : start_due_);
    for (const auto& p : procs_) {
      if (p.state == State::kBackoff) t = std::min(t, p.restart_at);
      if (p.state == State::kRunning && p.heard && p.spec.liveness_s > 0)
        t = std::min(
            t, std::max(std::max(p.last_heartbeat, bus_back_) + from_seconds(p.spec.liveness_s),
                        last_check_ + 100'000));
    }
  }
  for (const auto& p : procs_) {
    if (p.state == State::kSilent || (stopping_ && p.state == State::kStopping))
      t = std::min(t, p.kill_at);
  }
  return t;
}

std::string Supervisor::status_table(TimeUs now) const {
  std::size_t w = 4;
  for (const auto& p : procs_) w = std::max(w, p.spec.name.size());
  std::ostringstream os;
  auto pad = [](std::string s, std::size_t n) {
    if (s.size() < n) s.resize(n, ' ');
    return s;
  };
  os << pad("name", w) << "  " << pad("group", 10) << "  " << pad("state", 11) << "  "
     << pad("pid", 7) << "  " << pad("up_s", 7) << "  " << pad("hb_s", 6)
     << "  restarts  last exit\n";
  for (const auto& p : procs_) {
    const bool up =
        p.state == State::kRunning || p.state == State::kStopping || p.state == State::kSilent;
    char upbuf[32] = "-";
    if (up) std::snprintf(upbuf, sizeof upbuf, "%.1f", to_seconds(now - p.started_at));
    char hbbuf[32] = "-";  // seconds since its last heartbeat (watched processes)
    if (up && p.heard)
      std::snprintf(hbbuf, sizeof hbbuf, "%.1f", to_seconds(now - p.last_heartbeat));
    os << pad(p.spec.name, w) << "  " << pad(p.spec.group, 10) << "  "
       << pad(to_string(p.state), 11) << "  " << pad(p.pid > 0 ? std::to_string(p.pid) : "-", 7)
       << "  " << pad(upbuf, 7) << "  " << pad(hbbuf, 6) << "  "
       << pad(std::to_string(p.restarts), 8) << "  "
       << (p.has_exited ? p.last_exit.describe() : "-") << "\n";
  }
  return os.str();
}

}  // namespace tiller::launch
