// tiller-launch's heartbeat watchdog (docs/safety.md, "Stalls and liveness"). The Supervisor,
// told heartbeats and time (fake host, no fork): a process whose heartbeat is silent for its
// liveness_s is sent SIGTERM and SIGCONT, SIGKILL after the grace period, and its exit counts
// as a failure whatever its status, so its restart policy applies; a process is watched only
// from its first heartbeat; liveness_s: 0 is never watched. The launch file's keys. The
// launcher's node (LaunchMonitor) counts bad heartbeats and publishes the stop at once. Then
// the real thing (inside tools/netns-run): a SIGSTOPped tiller-mixer under tiller-launch, with
// signing on, is reported silent within liveness_s + 1 s, restarted, and the run's log holds
// the launcher's TILLER_HEARTBEAT_LAUNCH saying so.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <tiller/heartbeat_t.hpp>

#include "core/config.hpp"
#include "launch/launch_file.hpp"
#include "launch/monitor.hpp"
#include "launch/supervisor.hpp"
#include "runtime/event.hpp"
#include "runtime/log.hpp"

namespace tiller::launch {
namespace {

namespace fs = std::filesystem;

struct FakeHost : ProcessHost {
  int next_pid = 100;
  std::vector<std::string> spawned;
  std::vector<std::pair<int, int>> signals;  // (pid, sig)
  int spawn(const ProcessSpec& p, std::string&) override {
    spawned.push_back(p.name);
    return next_pid++;
  }
  void signal(int pid, int sig) override { signals.emplace_back(pid, sig); }
};

ProcessSpec proc(const std::string& name, Restart r = Restart::kOnFailure) {
  ProcessSpec p;
  p.name = name;
  p.command = name;
  p.restart = r;
  p.backoff_s = 0.5;
  p.backoff_max_s = 1.5;
  return p;
}

constexpr TimeUs s_(double s) {
  return static_cast<TimeUs>(s * 1e6);
}

TEST(Liveness, SilentHeartbeatStopsTheProcessThenItsRestartPolicyApplies) {
  FakeHost h;
  std::vector<std::string> notes;
  Supervisor s({proc("mixer"), proc("logger")}, "", 2.0, h,
               [&](const std::string& n) { notes.push_back(n); });
  s.start(0);
  const int pid = s.processes()[0].pid;
  // Not watched before its first heartbeat.
  s.poll(s_(10));
  EXPECT_TRUE(h.signals.empty());
  EXPECT_EQ(s.next_deadline(), INT64_MAX);
  ASSERT_TRUE(s.on_heartbeat("mixer", s_(11)));
  ASSERT_TRUE(s.on_heartbeat("mixer", s_(12)));
  EXPECT_EQ(s.next_deadline(), s_(15));  // last heartbeat + liveness_s (3 s default)
  s.poll(s_(15) - 1);
  EXPECT_TRUE(h.signals.empty());
  s.poll(s_(15));
  // SIGTERM first, then SIGCONT: a SIGSTOPped process wakes with SIGTERM pending.
  ASSERT_EQ(h.signals.size(), 2u);
  EXPECT_EQ(h.signals[0], std::make_pair(pid, SIGTERM));
  EXPECT_EQ(h.signals[1], std::make_pair(pid, SIGCONT));
  EXPECT_EQ(s.processes()[0].state, State::kSilent);
  EXPECT_EQ(s.silent_stops(), 1);
  EXPECT_EQ(s.last_silent(),
            "mixer: no heartbeat for 3.0 s (liveness_s 3): treated as failed, stopping it "
            "(SIGTERM and SIGCONT, SIGKILL after 2.0 s)");
  EXPECT_EQ(notes.back(), s.last_silent());
  // A heartbeat now (it woke up and said one more) does not save it.
  EXPECT_TRUE(s.on_heartbeat("mixer", s_(15.1)));
  EXPECT_EQ(s.next_deadline(), s_(17));  // the grace period
  s.poll(s_(17));
  ASSERT_EQ(h.signals.size(), 3u);
  EXPECT_EQ(h.signals[2], std::make_pair(pid, SIGKILL));
  s.on_exit(pid, ExitInfo{0, SIGKILL}, s_(17.1));
  const auto& m = s.processes()[0];
  EXPECT_EQ(m.state, State::kBackoff);  // on-failure: a silent process failed
  EXPECT_DOUBLE_EQ(m.last_exit.silent_s, 3.0);
  EXPECT_EQ(m.last_exit.describe(), "heartbeat silent 3.0 s, then killed by SIGKILL");
  EXPECT_EQ(notes.back(), "mixer exited (heartbeat silent 3.0 s, then killed by SIGKILL)");
  s.poll(s_(17.6));
  EXPECT_EQ(h.spawned, (std::vector<std::string>{"mixer", "logger", "mixer"}));
  EXPECT_EQ(s.processes()[0].restarts, 1);
  // The new instance is watched again only from its own first heartbeat.
  s.poll(s_(40));
  EXPECT_EQ(h.signals.size(), 3u);
  EXPECT_EQ(s.processes()[1].state, State::kRunning);  // the logger never said a heartbeat
}

TEST(Liveness, ACleanExitAfterSilenceStillCountsAsAFailure) {
  {  // on-failure restarts it
    FakeHost h;
    Supervisor s({proc("esc")}, "", 1.0, h);
    s.start(0);
    s.on_heartbeat("esc", s_(1));
    s.poll(s_(4));
    ASSERT_EQ(s.processes()[0].state, State::kSilent);
    s.on_exit(s.processes()[0].pid, ExitInfo{0, 0}, s_(4.05));  // its SIGTERM handler: exit 0
    EXPECT_EQ(s.processes()[0].state, State::kBackoff);
    EXPECT_TRUE(s.processes()[0].last_exit.failed());
    EXPECT_FALSE(s.processes()[0].killed);
  }
  {  // critical, restart never: the run stops with exit 3
    FakeHost h;
    auto c = proc("esc", Restart::kNever);
    c.critical = true;
    Supervisor s({proc("a"), c}, "", 1.0, h);
    s.start(0);
    s.on_heartbeat("esc", s_(1));
    s.poll(s_(4));
    s.on_exit(s.processes()[1].pid, ExitInfo{0, 0}, s_(4.05));
    EXPECT_TRUE(s.stopping());
    EXPECT_EQ(s.exit_status(), kExitCriticalFailed);
    EXPECT_NE(s.stop_reason().find("esc failed (heartbeat silent 3.0 s, then exit 0)"),
              std::string::npos)
        << s.stop_reason();
  }
}

TEST(Liveness, OwnLimitHeartbeatNameAndLivenessZero) {
  FakeHost h;
  auto a = proc("autopilot");
  a.heartbeat = "mixer";  // runs tiller-mixer under another name
  a.liveness_s = 5;
  auto b = proc("bridge");
  b.liveness_s = 0;  // not watched
  Supervisor s({a, b}, "", 1.0, h);
  s.start(0);
  EXPECT_FALSE(s.on_heartbeat("autopilot", s_(1)));  // its node is "mixer"
  EXPECT_TRUE(s.on_heartbeat("mixer", s_(1)));
  EXPECT_FALSE(s.on_heartbeat("bridge", s_(1)));
  EXPECT_FALSE(s.on_heartbeat("nobody", s_(1)));
  s.poll(s_(5.9));
  EXPECT_TRUE(h.signals.empty());
  s.poll(s_(6));
  ASSERT_EQ(h.signals.size(), 2u);
  EXPECT_EQ(h.signals[0].first, s.processes()[0].pid);
  EXPECT_EQ(s.processes()[1].state, State::kRunning);
}

TEST(Liveness, OrderlyStopWhileAProcessIsBeingStoppedForSilence) {
  FakeHost h;
  Supervisor s({proc("a"), proc("b")}, "", 2.0, h);
  s.start(0);
  const int a = s.processes()[0].pid, b = s.processes()[1].pid;
  s.on_heartbeat("b", s_(1));
  s.poll(s_(4));  // b silent: SIGTERM + SIGCONT, SIGKILL due at 6 s
  ASSERT_EQ(h.signals.size(), 2u);
  s.request_stop(s_(4.5), "SIGINT");
  EXPECT_EQ(h.signals.size(), 2u);  // b is not signalled twice; a waits for b (reverse order)
  s.poll(s_(6));
  ASSERT_EQ(h.signals.size(), 3u);
  EXPECT_EQ(h.signals[2], std::make_pair(b, SIGKILL));
  s.on_exit(b, ExitInfo{0, SIGKILL}, s_(6.1));
  EXPECT_EQ(s.processes()[1].state, State::kExited);  // not restarted while stopping
  EXPECT_EQ(h.signals.back(), std::make_pair(a, SIGTERM));
  s.on_exit(a, ExitInfo{0, SIGTERM}, s_(6.2));
  EXPECT_TRUE(s.finished());
}

// The launcher hears nothing at all (its own heartbeat does not come back: the multicast route
// went with the link): no process is judged; when the bus is back, silence counts from then.
TEST(Liveness, NoVerdictWhileTheBusIsDown) {
  FakeHost h;
  Supervisor s({proc("teleop")}, "", 1.0, h);
  s.start(0);
  for (double t = 0.5; t < 3; t += 1) s.on_bus(s_(t));  // echoes at 0.5, 1.5, 2.5 s
  s.on_heartbeat("teleop", s_(1));
  s.on_heartbeat("teleop", s_(2));  // then the link goes down at 2.7 s: nothing more arrives
  for (double t = 3; t < 12; t += 0.5) s.poll(s_(t));
  EXPECT_TRUE(h.signals.empty());
  s.on_bus(s_(12));  // back, but the teleop is really gone now
  s.poll(s_(14.9));
  EXPECT_TRUE(h.signals.empty());
  for (double t = 13; t < 16; t += 1) s.on_bus(s_(t));
  s.poll(s_(15));  // 3 s since the bus came back
  ASSERT_EQ(h.signals.size(), 2u);
  EXPECT_EQ(s.processes()[0].state, State::kSilent);
}

LaunchFile parse(const std::string& text) {
  return load_launch(config::Value::parse(text, "l.yaml"), "/tmp");
}

TEST(Liveness, LaunchFileKeys) {
  const auto lf = parse(
      "name: l\nroot: .\nliveness_s: 4\nprocesses:\n  - {name: a, command: a}\n"
      "  - {name: b, command: b, liveness_s: 0}\n  - {name: c, command: c, liveness_s: 2.5, "
      "heartbeat: mixer}\n");
  EXPECT_EQ(lf.liveness_s, 4);
  EXPECT_EQ(lf.processes[0].liveness_s, 4);
  EXPECT_EQ(lf.processes[0].heartbeat_node(), "a");
  EXPECT_EQ(lf.processes[1].liveness_s, 0);
  EXPECT_EQ(lf.processes[2].liveness_s, 2.5);
  EXPECT_EQ(lf.processes[2].heartbeat_node(), "mixer");
  EXPECT_EQ(
      parse("name: l\nroot: .\nprocesses:\n  - {name: a, command: a}\n").processes[0].liveness_s,
      3.0);
  auto error_of = [](const std::string& t) {
    try {
      parse(t);
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string expected =
      "liveness_s: expected 0 (not watched) or a number of seconds from 1.5 to 3600 (heartbeats "
      "come once a second)";
  EXPECT_NE(error_of("name: l\nroot: .\nprocesses:\n  - {name: a, command: a, liveness_s: 1}\n")
                .find("l.yaml:4: processes[0]." + expected),
            std::string::npos);
  EXPECT_NE(error_of("name: l\nroot: .\nliveness_s: 0.5\nprocesses:\n  - {name: a, command: a}\n")
                .find("l.yaml:3: " + expected),
            std::string::npos);
  EXPECT_NE(error_of("name: l\nroot: .\nprocesses:\n  - {name: a, command: a, liveness_s: -1}\n")
                .find("liveness_s"),
            std::string::npos);
  EXPECT_NE(error_of("name: l\nroot: .\nprocesses:\n  - {name: a, command: a, heartbeat: 'a b'}\n")
                .find("heartbeat: expected a node name"),
            std::string::npos);
}

// The launcher's node, driven by hand (no LCM): what it hears and what it says.
struct Capture : Bus {
  std::vector<Event> out;
  void publish(std::string_view ch, const std::uint8_t* d, int n) override {
    out.push_back(Event{std::string(ch), 0, std::vector<std::uint8_t>(d, d + n)});
  }
};

Event heartbeat_of(const std::string& node, TimeUs t) {
  heartbeat_t hb{};
  hb.utime = t;
  hb.process = node;
  hb.status = "ok";
  return encode("TILLER_HEARTBEAT_" + node, t, hb);
}

std::int64_t counter_in(const heartbeat_t& hb, const std::string& name) {
  for (int i = 0; i < hb.n_counters; ++i)
    if (hb.counter_names[static_cast<std::size_t>(i)] == name)
      return hb.counter_values[static_cast<std::size_t>(i)];
  return -1;
}

TEST(Liveness, LauncherNodeHearsHeartbeatsAndPublishesTheStopAtOnce) {
  FakeHost h;
  auto logger = proc("logger");
  logger.liveness_s = 0;
  Supervisor s({logger, proc("mixer"), proc("esc")}, "", 2.0, h);
  LaunchMonitor m(s);
  Capture bus;
  m.attach(&bus);
  // Watched channels only, the logger's not.
  EXPECT_EQ(m.subscribed_channels(),
            (std::vector<std::string>{"TILLER_HEARTBEAT_ESC", "TILLER_HEARTBEAT_LAUNCH",
                                      "TILLER_HEARTBEAT_MIXER"}));
  EXPECT_EQ(*m.allowed_senders("TILLER_HEARTBEAT_ESC"), (std::vector<std::string>{"esc"}));
  s.start(0);
  auto e = heartbeat_of("esc", s_(1));
  e.channel = "TILLER_HEARTBEAT_ESC";
  m.deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), s_(1));
  EXPECT_TRUE(s.processes()[2].heard);
  // A heartbeat that fails its checks (a negative counter), and one from a node nobody
  // watches on a watched channel: dropped and counted, the process not heard.
  heartbeat_t bad{};
  bad.process = "mixer";
  bad.n_counters = 1;
  bad.counter_names = {"x"};
  bad.counter_values = {-1};
  auto b = encode("TILLER_HEARTBEAT_MIXER", 0, bad);
  m.deliver(b.channel, b.data.data(), static_cast<int>(b.data.size()), s_(1));
  auto u = heartbeat_of("stranger", s_(1));
  m.deliver("TILLER_HEARTBEAT_MIXER", u.data.data(), static_cast<int>(u.data.size()), s_(1));
  EXPECT_FALSE(s.processes()[1].heard);
  EXPECT_EQ(m.counter_value("rejected.heartbeat.invalid"), 1);
  EXPECT_EQ(m.counter_value("rejected.heartbeat.unknown"), 1);
  m.tick(s_(2));
  ASSERT_EQ(bus.out.size(), 1u);
  heartbeat_t hb;
  ASSERT_TRUE(decode(bus.out[0], hb));
  EXPECT_EQ(bus.out[0].channel, "TILLER_HEARTBEAT_LAUNCH");
  EXPECT_EQ(hb.state, heartbeat_t::STATE_OK);
  EXPECT_EQ(hb.status, "2 processes watched (liveness)");
  // esc goes silent: the stop is published at once, not at the next whole second.
  s.poll(s_(4.2));
  m.after_poll(s_(4.2));
  ASSERT_EQ(bus.out.size(), 2u);
  ASSERT_TRUE(decode(bus.out[1], hb));
  EXPECT_EQ(hb.utime, s_(4.2));
  EXPECT_EQ(hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_EQ(hb.status.rfind("esc: no heartbeat for 3.2 s (liveness_s 3)", 0), 0u) << hb.status;
  EXPECT_EQ(counter_in(hb, "watchdog.silent.esc"), 1);
  EXPECT_EQ(counter_in(hb, "watchdog.silent.mixer"), 0);
  m.after_poll(s_(4.3));
  EXPECT_EQ(bus.out.size(), 2u);  // once per stop
  s.on_exit(s.processes()[2].pid, ExitInfo{0, 0}, s_(4.4));
  s.poll(s_(5));  // restarted after its 0.5 s back-off
  m.tick(s_(5));
  ASSERT_TRUE(decode(bus.out.back(), hb));
  EXPECT_EQ(counter_in(hb, "restarts.esc"), 1);
  EXPECT_EQ(hb.state, heartbeat_t::STATE_OK);
}

// ---------------------------------------------------------------- the real launcher (netns)
template <class F>
bool wait_for(F cond, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (cond()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return cond();
}

std::string slurp(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The status file's row of `name`: state, pid, hb_s.
struct Row {
  std::string state, pid, hb;
};
Row row_of(const fs::path& status, const std::string& name) {
  std::istringstream in(slurp(status));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string n, group, up;
    Row r;
    l >> n >> group >> r.state >> r.pid >> up >> r.hb;
    if (n == name) return r;
  }
  return {};
}

TEST(LivenessProcess, StoppedMixerIsReportedSilentWithinLivenessPlusOneSecondAndRestarted) {
  const fs::path dir = fs::temp_directory_path() / ("tiller-liveness-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const double liveness = 2.0;
  std::ofstream(dir / "run.yaml")
      << "name: live\nroot: .\ngrace_s: 1\nliveness_s: " << liveness << "\n"
      << "key_file: sim.key\ncreate_key: true\nrequire_signed: true\n"
      << "logger: {enabled: true, dir: logs}\nprocesses:\n"
      << "  - name: mixer\n    command: tiller-mixer\n    args: [--config, " TILLER_SOURCE_DIR
         "/config/mixer/otter.yaml]\n    restart: on-failure\n    backoff_s: 0.2\n";
  const pid_t launcher = ::fork();
  if (launcher == 0) {
    std::freopen((dir / "out.txt").c_str(), "w", stdout);
    const std::string bin = std::string(TILLER_BIN_DIR) + "/tiller-launch";
    ::execl(bin.c_str(), bin.c_str(), (dir / "run.yaml").c_str(),
            ("--status-file=" + (dir / "status").string()).c_str(),
            ("--log-file=" + (dir / "run.lcmlog").string()).c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Watched once its first heartbeat has come (hb_s is a number).
  ASSERT_TRUE(wait_for(
      [&] {
        const Row r = row_of(dir / "status", "mixer");
        return r.state == "running" && r.hb != "-" && !r.hb.empty();
      },
      15))
      << slurp(dir / "out.txt") << slurp(dir / "status");
  const int pid1 = std::stoi(row_of(dir / "status", "mixer").pid);
  ASSERT_EQ(::kill(pid1, SIGSTOP), 0);
  const auto stopped = std::chrono::steady_clock::now();
  ASSERT_TRUE(wait_for(
      [&] { return slurp(dir / "out.txt").find("mixer: no heartbeat for") != std::string::npos; },
      liveness + 3))
      << slurp(dir / "out.txt");
  const double reported =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stopped).count();
  std::printf("SIGSTOP -> reported silent: %.2f s (liveness_s %.1f)\n", reported, liveness);
  EXPECT_LE(reported, liveness + 1.0);
  // SIGCONT + SIGTERM let it shut down cleanly; the policy (on-failure) restarts it.
  ASSERT_TRUE(wait_for(
      [&] {
        const Row r = row_of(dir / "status", "mixer");
        return r.state == "running" && !r.pid.empty() && r.pid != "-" && std::stoi(r.pid) != pid1;
      },
      5))
      << slurp(dir / "out.txt");
  EXPECT_NE(::kill(pid1, 0), 0);  // the stopped one is gone (reaped)
  ::kill(launcher, SIGTERM);
  int st = 0;
  ::waitpid(launcher, &st, 0);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
  const std::string out = slurp(dir / "out.txt");
  EXPECT_NE(out.find("liveness: heartbeats watched from each process's first one: mixer (2 s"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("mixer exited (heartbeat silent 2."), std::string::npos) << out;
  EXPECT_NE(out.find("restarting mixer (restart 1)"), std::string::npos) << out;
  // The log has the launcher's heartbeat saying so (signed: read_log strips the trailer).
  bool said = false;
  for (const auto& e : read_log((dir / "run.lcmlog").string(), "TILLER_HEARTBEAT_LAUNCH")) {
    heartbeat_t hb;
    if (!decode(e, hb)) continue;
    if (hb.status.rfind("mixer: no heartbeat for", 0) == 0 &&
        counter_in(hb, "watchdog.silent.mixer") == 1 && hb.state == heartbeat_t::STATE_DEGRADED)
      said = true;
  }
  EXPECT_TRUE(said) << "no TILLER_HEARTBEAT_LAUNCH about the stop in the log";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tiller::launch
