// tiller-launch: the launch-file loader refuses bad files with the line and key; the
// supervision state machine (fake host, no fork) restarts per policy with back-off and a
// limit and stops in reverse order with SIGTERM then SIGKILL; the real launcher (fork/exec
// of small shell processes) restarts a killed process, stops everything on SIGTERM with no
// orphan, and takes its children down when it is SIGKILLed itself.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/config.hpp"
#include "core/lcm_url.hpp"
#include "launch/launch_file.hpp"
#include "launch/posix_host.hpp"
#include "launch/supervisor.hpp"

namespace tiller::launch {
namespace {

namespace fs = std::filesystem;

LaunchFile parse(const std::string& text) {
  return load_launch(config::Value::parse(text, "bad.yaml"), "/tmp");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

const char* kGood = R"(name: good
root: .
processes:
  - name: sim
    command: tiller-sim
  - name: mixer
    command: tiller-mixer
    depends_on: [esc]
    restart: on-failure
  - name: esc
    command: tiller-esc
    group: hw
)";

TEST(LaunchFile, LoadsAndOrdersByDependency) {
  const LaunchFile lf = parse(kGood);
  ASSERT_EQ(lf.processes.size(), 3u);
  EXPECT_EQ(lf.processes[0].name, "sim");
  EXPECT_EQ(lf.processes[1].name, "esc");  // before mixer, which depends on it
  EXPECT_EQ(lf.processes[2].name, "mixer");
  EXPECT_EQ(lf.processes[2].restart, Restart::kOnFailure);
  EXPECT_EQ(lf.processes[2].line, 6);
  EXPECT_EQ(select(lf, {"hw"}, {}), (std::vector<std::size_t>{1}));
  EXPECT_EQ(select(lf, {"hw"}, {"sim"}), (std::vector<std::size_t>{0, 1}));
  EXPECT_THROW(select(lf, {"nope"}, {}), std::invalid_argument);
}

TEST(LaunchFile, BadFilesAreRefusedWithLineAndKey) {
  EXPECT_EQ(
      error_of(
          "name: x\nroot: .\nprocesses:\n  - name: a\n    command: b\n    restart: sometimes\n"),
      "bad.yaml:6: processes[0].restart: expected one of: never, on-failure, always, got "
      "'sometimes'");
  EXPECT_NE(
      error_of("name: x\nroot: .\nprocesses:\n  - name: a\n    command: b\n    restrat: always\n")
          .find("bad.yaml:6: processes[0].restrat"),
      std::string::npos);
  EXPECT_NE(
      error_of("name: x\nroot: .\nprocesses:\n  - name: a\n    command: b\n    depends_on: [c]\n")
          .find("bad.yaml:6: processes[0].depends_on[0]: expected the name of another process"),
      std::string::npos);
  EXPECT_NE(error_of("name: x\nroot: .\nprocesses:\n  - name: a\n    command: b\n  - name: a\n    "
                     "command: c\n")
                .find("bad.yaml:6: processes[1].name: expected a name not used by another process"),
            std::string::npos);
  const std::string cycle = error_of(
      "name: x\nroot: .\nprocesses:\n  - name: a\n    command: b\n    depends_on: [c]\n"
      "  - name: c\n    command: d\n    depends_on: [a]\n");
  EXPECT_NE(cycle.find("depends_on: expected dependencies without a cycle"), std::string::npos)
      << cycle;
  EXPECT_NE(error_of("name: x\nroot: .\nprocesses: []\n")
                .find("bad.yaml:3: processes: expected a non-empty"),
            std::string::npos);
  EXPECT_NE(error_of("name: x\nroot: .\nlcm_url: udpm://239.255.76.67:7667?ttl=2\nprocesses:\n  - "
                     "{name: a, command: b}\n")
                .find("bad.yaml:3: lcm_url: expected a udpm:// URL with ttl=0 (this computer only) "
                      "or ttl=1 (topside and vehicle computers on one link), got ttl=2"),
            std::string::npos);
  EXPECT_NE(error_of("name: x\nroot: .\nends_with: zz\nprocesses:\n  - {name: a, command: b}\n")
                .find("bad.yaml:3: ends_with"),
            std::string::npos);
  EXPECT_NE(error_of("name: x\nroot: .\nprocesses:\n  - {name: a, command: b, backoff_s: -1}\n")
                .find("bad.yaml:4: processes[0].backoff_s"),
            std::string::npos);
}

// One TTL rule (core/lcm_url.hpp) for a launch file's lcm_url and every program's --lcm-url:
// ttl=0 and ttl=1 (two computers on one link) are taken, ttl=2 and a non-number are refused by
// both with the same words.
TEST(LaunchFile, TtlOneIsTakenAndTtlTwoRefusedByTheFileAndByLcmUrlAlike) {
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?ttl=0"), "");
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?ttl=1"), "");
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667"), "");
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?recv_buf_size=2097152&ttl=1"), "");
  EXPECT_EQ(lcm_url_problem("memq://"), "");
  EXPECT_EQ(lcm_url_ttl("udpm://239.255.76.67:7667?ttl=1"), 1);
  EXPECT_EQ(lcm_url_ttl("udpm://239.255.76.67:7667?ttl=10"), 10);
  EXPECT_EQ(lcm_url_ttl("udpm://239.255.76.67:7667?ttl=x"), -1);
  const std::string expected =
      "a udpm:// URL with ttl=0 (this computer only) or ttl=1 (topside and vehicle computers on "
      "one link), got ttl=";
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?ttl=2"), expected + "2");
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?ttl=10"), expected + "10");
  EXPECT_EQ(lcm_url_problem("udpm://239.255.76.67:7667?ttl=01x"), expected + "01x");

  const fs::path dir = fs::temp_directory_path() / ("tiller-ttl-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "out.txt").string();
  auto launch = [&](const std::string& url_in_file, const std::string& option) {
    std::ofstream(dir / "l.yaml") << "name: l\nroot: .\nlcm_url: " << url_in_file
                                  << "\nprocesses:\n  - {name: a, command: sh}\n";
    const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-launch --check " +
                            (dir / "l.yaml").string() + " " + option + " > " + out + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::stringstream ss;
    ss << std::ifstream(out).rdbuf();
    return std::make_pair(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str());
  };
  const std::string one = "udpm://239.255.76.67:7667?ttl=1",
                    two = "udpm://239.255.76.67:7667?ttl=2";
  auto [rc1, o1] = launch(one, "");
  EXPECT_EQ(rc1, 0) << o1;
  EXPECT_NE(o1.find("ttl=1"), std::string::npos) << o1;
  auto [rc2, o2] = launch("udpm://239.255.76.67:7667?ttl=0", "--lcm-url '" + one + "'");
  EXPECT_EQ(rc2, 0) << o2;
  EXPECT_NE(o2.find("ttl=1"), std::string::npos) << o2;
  auto [rc3, o3] = launch(two, "");
  EXPECT_EQ(rc3, 2) << o3;
  EXPECT_NE(o3.find("lcm_url: expected " + expected + "2"), std::string::npos) << o3;
  auto [rc4, o4] = launch("udpm://239.255.76.67:7667?ttl=0", "--lcm-url '" + two + "'");
  EXPECT_EQ(rc4, 2) << o4;
  EXPECT_NE(o4.find("--lcm-url: expected " + expected + "2"), std::string::npos) << o4;
  fs::remove_all(dir);
}

TEST(LaunchFile, Substitution) {
  EXPECT_EQ(substitute("--lcm-url=${LCM_URL}", {{"LCM_URL", "udpm://x"}}), "--lcm-url=udpm://x");
  EXPECT_THROW(substitute("${TILLER_NO_SUCH_VARIABLE_42}", {}), std::invalid_argument);
  EXPECT_EQ(substitute("--m=${TILLER_NO_SUCH_VARIABLE_42:-a/b.yaml}", {}), "--m=a/b.yaml");
  EXPECT_EQ(substitute("${LCM_URL:-x}", {{"LCM_URL", "y"}}), "y");
}

// ${RUN_DIR}: a new directory per run, 0700, under $TMPDIR, gone with what is in it at the end.
TEST(LaunchFile, RunDirIsPrivateAndRemovedWithItsContents) {
  const fs::path base = fs::temp_directory_path() / ("tiller-rundir-" + std::to_string(::getpid()));
  fs::create_directories(base);
  ::setenv("TMPDIR", base.c_str(), 1);
  std::string path;
  {
    const RunDir a("my launch/x"), b("my launch/x");
    path = a.path();
    EXPECT_NE(a.path(), b.path());
    EXPECT_EQ(fs::path(a.path()).parent_path(), base);
    EXPECT_EQ(fs::path(a.path()).filename().string().rfind("tiller-my_launch_x-", 0), 0u);
    EXPECT_EQ(fs::status(a.path()).permissions(), fs::perms::owner_all);
    fs::create_directories(a.path() + "/sub");
    std::ofstream(a.path() + "/sub/gpsd.sock") << "x";
    fs::create_symlink("/dev/null", a.path() + "/gps0");
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::exists("/dev/null"));  // a link in it is removed, not its target
  ::setenv("TMPDIR", (base / "missing").c_str(), 1);
  EXPECT_THROW(RunDir("x"), std::runtime_error);
  ::unsetenv("TMPDIR");
  fs::remove_all(base);
}

// ---------------------------------------------------------------- supervisor, fake host
struct FakeHost : ProcessHost {
  int next_pid = 100;
  std::vector<std::string> spawned;          // names in spawn order
  std::vector<std::pair<int, int>> signals;  // (pid, sig)
  std::map<int, std::string> name_of;
  bool fail_spawn = false;
  int spawn(const ProcessSpec& p, std::string& error) override {
    if (fail_spawn) {
      error = "no such program";
      return -1;
    }
    spawned.push_back(p.name);
    name_of[next_pid] = p.name;
    return next_pid++;
  }
  void signal(int pid, int sig) override { signals.emplace_back(pid, sig); }
  std::map<std::string, TimeUs> written;  // path -> when it got data (fake files)
  bool file_has_data(const std::string& path, TimeUs since) override {
    auto it = written.find(path);
    return it != written.end() && it->second >= since;
  }
};

ProcessSpec proc(const std::string& name, Restart r = Restart::kNever, int max_restarts = 5) {
  ProcessSpec p;
  p.name = name;
  p.command = name;
  p.restart = r;
  p.backoff_s = 0.5;
  p.backoff_max_s = 1.5;
  p.max_restarts = max_restarts;
  return p;
}

int pid_of(const Supervisor& s, const std::string& name) {
  for (const auto& p : s.processes())
    if (p.spec.name == name) return p.pid;
  return -1;
}

TEST(Supervisor, RestartsOnFailureWithBackoffThenGivesUp) {
  FakeHost h;
  Supervisor s({proc("a"), proc("b", Restart::kOnFailure, 3)}, "", 2.0, h);
  s.start(0);
  ASSERT_EQ(h.spawned, (std::vector<std::string>{"a", "b"}));
  // Exits: back-off 0.5 s, 1.0 s, 1.5 s (doubling, capped), then given up.
  const TimeUs expected_delay[] = {500'000, 1'000'000, 1'500'000};
  TimeUs t = 1'000'000;
  for (int k = 0; k < 3; ++k) {
    s.on_exit(pid_of(s, "b"), ExitInfo{1, 0}, t);
    EXPECT_EQ(s.processes()[1].state, State::kBackoff);
    EXPECT_EQ(s.next_deadline(), t + expected_delay[k]);
    s.poll(t + expected_delay[k] - 1);
    EXPECT_EQ(h.spawned.size(), 2u + k);  // not yet
    s.poll(t + expected_delay[k]);
    EXPECT_EQ(h.spawned.size(), 3u + k);
    EXPECT_EQ(s.processes()[1].restarts, k + 1);
    t += expected_delay[k] + 100'000;
  }
  s.on_exit(pid_of(s, "b"), ExitInfo{0, SIGSEGV}, t);
  EXPECT_EQ(s.processes()[1].state, State::kGaveUp);
  EXPECT_FALSE(s.stopping());  // a is still running; b was not critical
  // on-failure does not restart a clean exit; never does not restart at all.
  s.on_exit(pid_of(s, "a"), ExitInfo{0, 0}, t);
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.exit_status(), kExitRunFailed);  // b failed for good
}

TEST(Supervisor, AlwaysRestartsACleanExitAndStableRunResetsTheStreak) {
  FakeHost h;
  auto p = proc("a", Restart::kAlways, 1);
  p.stable_after_s = 10;
  Supervisor s({p}, "", 2.0, h);
  s.start(0);
  s.on_exit(pid_of(s, "a"), ExitInfo{0, 0}, 1'000'000);
  s.poll(1'500'000);
  EXPECT_EQ(h.spawned.size(), 2u);
  // Ran 20 s (> stable_after_s): the limit of 1 starts again.
  s.on_exit(pid_of(s, "a"), ExitInfo{0, 0}, 21'500'000);
  EXPECT_EQ(s.processes()[0].state, State::kBackoff);
  s.poll(22'000'000);
  EXPECT_EQ(h.spawned.size(), 3u);
  // Quick exit again: the streak is used up.
  s.on_exit(pid_of(s, "a"), ExitInfo{0, 0}, 22'100'000);
  EXPECT_EQ(s.processes()[0].state, State::kGaveUp);
  EXPECT_EQ(s.processes()[0].restarts, 2);
}

TEST(Supervisor, EndsWithProcessStopsAllInReverseOrderSigtermThenSigkill) {
  FakeHost h;
  Supervisor s({proc("logger"), proc("sim"), proc("mixer"), proc("mission")}, "mission", 2.0, h);
  s.start(0);
  const int sim = pid_of(s, "sim"), mixer = pid_of(s, "mixer"), logger = pid_of(s, "logger");
  s.on_exit(pid_of(s, "mission"), ExitInfo{0, 0}, 5'000'000);
  ASSERT_TRUE(s.stopping());
  ASSERT_EQ(h.signals.size(), 1u);
  EXPECT_EQ(h.signals[0], std::make_pair(mixer, SIGTERM));  // last started first, one at a time
  s.on_exit(mixer, ExitInfo{0, SIGTERM}, 5'100'000);
  EXPECT_EQ(h.signals.back(), std::make_pair(sim, SIGTERM));
  s.poll(7'099'999);
  EXPECT_EQ(h.signals.size(), 2u);
  s.poll(7'100'000);  // grace over: SIGKILL
  EXPECT_EQ(h.signals.back(), std::make_pair(sim, SIGKILL));
  s.on_exit(sim, ExitInfo{0, SIGKILL}, 7'200'000);
  EXPECT_TRUE(s.processes()[1].killed);
  EXPECT_EQ(h.signals.back(), std::make_pair(logger, SIGTERM));
  EXPECT_FALSE(s.finished());
  s.on_exit(logger, ExitInfo{0, 0}, 7'300'000);
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.exit_status(), kExitOk);
}

TEST(Supervisor, FailedEndsWithProcessGivesExitOneAndCriticalGivesThree) {
  {
    FakeHost h;
    Supervisor s({proc("a"), proc("mission")}, "mission", 1.0, h);
    s.start(0);
    s.on_exit(pid_of(s, "mission"), ExitInfo{4, 0}, 10);
    s.on_exit(pid_of(s, "a"), ExitInfo{0, SIGTERM}, 20);
    EXPECT_TRUE(s.finished());
    EXPECT_EQ(s.exit_status(), kExitRunFailed);
  }
  {
    FakeHost h;
    auto c = proc("esc", Restart::kOnFailure, 0);
    c.critical = true;
    Supervisor s({proc("a"), c}, "", 1.0, h);
    s.start(0);
    s.on_exit(pid_of(s, "esc"), ExitInfo{1, 0}, 10);
    EXPECT_TRUE(s.stopping());
    s.on_exit(pid_of(s, "a"), ExitInfo{0, SIGTERM}, 20);
    EXPECT_EQ(s.exit_status(), kExitCriticalFailed);
  }
}

TEST(Supervisor, StartDelaysAndStopBeforeEverythingStarted) {
  FakeHost h;
  auto b = proc("b");
  b.start_delay_s = 1.0;
  Supervisor s({proc("a"), b}, "", 1.0, h);
  s.start(0);
  EXPECT_EQ(h.spawned.size(), 1u);
  EXPECT_EQ(s.next_deadline(), 1'000'000);
  s.request_stop(500'000, "SIGINT");
  EXPECT_EQ(s.processes()[1].state, State::kNotStarted);
  s.on_exit(pid_of(s, "a"), ExitInfo{0, SIGTERM}, 600'000);
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(h.spawned.size(), 1u);
}

// The process after lcm-logger waits for the log file to have data written in this run (an old
// file of the same name does not count), and past start_after_file_max_s starts anyway, saying
// so. Before this, a logger slower than the 0.3 s delay lost the operator's START of the main
// job, and its replay failed (CI, stop 41).
TEST(Supervisor, TheFirstProcessWaitsForTheLoggersFirstWrite) {
  FakeHost h;
  auto b = proc("b");
  b.start_delay_s = 0.3;
  b.start_after_file = "/logs/run.lcmlog";
  b.start_after_file_max_s = 10.0;
  h.written["/logs/run.lcmlog"] = 5'000;  // a previous run's file, before this start
  std::vector<std::string> said;
  Supervisor s({proc("logger"), b, proc("c")}, "", 1.0, h,
               [&](const std::string& m) { said.push_back(m); });
  s.start(10'000);
  s.poll(400'000);
  EXPECT_EQ(h.spawned, (std::vector<std::string>{"logger"}));
  EXPECT_TRUE(s.waiting_for_file());
  EXPECT_EQ(s.next_deadline(), 420'000);  // polls the file every 20 ms
  s.poll(2'000'000);
  EXPECT_EQ(h.spawned.size(), 1u);
  h.written["/logs/run.lcmlog"] = 2'100'000;  // the logger's first flush
  s.poll(2'120'000);
  EXPECT_EQ(h.spawned, (std::vector<std::string>{"logger", "b", "c"}));
  EXPECT_FALSE(s.waiting_for_file());

  FakeHost h2;  // a logger that never writes: b starts 10 s after it was due, with a warning
  said.clear();
  Supervisor s2({proc("logger"), b}, "", 1.0, h2, [&](const std::string& m) { said.push_back(m); });
  s2.start(0);
  s2.poll(10'299'000);
  EXPECT_EQ(h2.spawned.size(), 1u);
  s2.poll(10'300'000);
  EXPECT_EQ(h2.spawned, (std::vector<std::string>{"logger", "b"}));
  bool warned = false;
  for (const auto& m : said)
    warned |= m.find("warning: /logs/run.lcmlog is still empty after 10 s: starting b") == 0;
  EXPECT_TRUE(warned);
}

TEST(Supervisor, ProgramThatCannotStartFollowsItsPolicy) {
  FakeHost h;
  h.fail_spawn = true;
  Supervisor s({proc("a", Restart::kOnFailure, 1)}, "", 1.0, h);
  s.start(0);
  EXPECT_EQ(s.processes()[0].state, State::kBackoff);
  s.poll(500'000);
  EXPECT_EQ(s.processes()[0].state, State::kGaveUp);
  EXPECT_TRUE(s.finished());
  EXPECT_EQ(s.exit_status(), kExitRunFailed);
}

// ---------------------------------------------------------------- the real launcher
// Alive and not a zombie (an orphan reparented to an init that has not reaped it yet is dead).
bool alive(int pid) {
  if (::kill(pid, 0) != 0) return false;
  std::ifstream st("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(st, line);
  const auto close = line.rfind(')');
  return close == std::string::npos || close + 2 >= line.size() || line[close + 2] != 'Z';
}

int read_pid(const fs::path& f) {
  std::ifstream in(f);
  int pid = -1;
  in >> pid;
  return pid;
}

template <class F>
bool wait_for(F cond, double seconds = 10) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (cond()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return cond();
}

struct Launcher {
  pid_t pid = -1;
  fs::path dir;
  explicit Launcher(const std::string& yaml) {
    dir = fs::temp_directory_path() /
          ("tiller-launch-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "run.yaml") << yaml;
    pid = ::fork();
    if (pid == 0) {
      const std::string out = (dir / "out.txt").string();
      std::freopen(out.c_str(), "w", stdout);
      const std::string bin = std::string(TILLER_BIN_DIR) + "/tiller-launch";
      const std::string file = (dir / "run.yaml").string();
      const std::string status = "--status-file=" + (dir / "status").string();
      ::execl(bin.c_str(), bin.c_str(), file.c_str(), status.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
  int wait_exit() {
    int st = 0;
    ::waitpid(pid, &st, 0);
    pid = -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  }
  std::string output() const {
    std::ifstream in(dir / "out.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  ~Launcher() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    fs::remove_all(dir);
  }
};

// A process that writes its pid (and its background child's pid) and sleeps.
std::string sleeper(const std::string& name, const std::string& extra = "") {
  return "  - name: " + name + "\n    command: sh\n    args: [-c, 'sleep 300 & echo $! > " + name +
         ".child; echo $$ > " + name + ".pid; echo up; wait']\n" + extra;
}

TEST(LaunchProcess, KilledProcessIsRestartedPerPolicy) {
  Launcher l("name: t\nroot: .\ngrace_s: 1\nlogger: {enabled: false}\nprocesses:\n" +
             sleeper("keep", "    restart: on-failure\n    backoff_s: 0.1\n") + sleeper("once"));
  ASSERT_TRUE(
      wait_for([&] { return fs::exists(l.dir / "keep.pid") && fs::exists(l.dir / "once.pid"); }));
  ASSERT_TRUE(wait_for(
      [&] { return read_pid(l.dir / "keep.pid") > 0 && read_pid(l.dir / "once.pid") > 0; }));
  const int keep1 = read_pid(l.dir / "keep.pid");
  const int once1 = read_pid(l.dir / "once.pid");
  fs::remove(l.dir / "keep.pid");
  ASSERT_EQ(::kill(keep1, SIGKILL), 0);
  ASSERT_EQ(::kill(once1, SIGKILL), 0);
  ASSERT_TRUE(
      wait_for([&] { return fs::exists(l.dir / "keep.pid") && read_pid(l.dir / "keep.pid") > 0; }));
  const int keep2 = read_pid(l.dir / "keep.pid");
  EXPECT_NE(keep2, keep1);
  EXPECT_TRUE(alive(keep2));
  ::kill(l.pid, SIGTERM);
  EXPECT_EQ(l.wait_exit(), kExitOk);
  const std::string out = l.output();
  EXPECT_NE(out.find("keep   | up"), std::string::npos) << out;
  EXPECT_NE(out.find("once exited (killed by SIGKILL)"), std::string::npos) << out;
  EXPECT_NE(out.find("restarting keep (restart 1)"), std::string::npos) << out;
  EXPECT_EQ(out.find("restarting once"), std::string::npos) << out;  // policy never
  EXPECT_FALSE(alive(keep2));
}

TEST(LaunchProcess, SigtermStopsEverythingWithNoOrphan) {
  Launcher l("name: t\nroot: .\ngrace_s: 0.5\nlogger: {enabled: false}\nprocesses:\n" +
             sleeper("a") + sleeper("b") +
             "  - name: deaf\n    command: sh\n    args: [-c, \"trap '' TERM; echo $$ > deaf.pid; "
             "while :; do sleep 0.05; done\"]\n");
  std::vector<int> pids;
  ASSERT_TRUE(wait_for([&] {
    for (const char* f : {"a.pid", "a.child", "b.pid", "b.child", "deaf.pid"})
      if (read_pid(l.dir / f) <= 0) return false;
    return true;
  }));
  for (const char* f : {"a.pid", "a.child", "b.pid", "b.child", "deaf.pid"})
    pids.push_back(read_pid(l.dir / f));
  for (int p : pids) EXPECT_TRUE(alive(p)) << p;
  ::kill(l.pid, SIGTERM);
  EXPECT_EQ(l.wait_exit(), kExitOk);
  // Children were reaped by the launcher (or, for grandchildren, killed with their group).
  for (int p : pids) EXPECT_TRUE(wait_for([&] { return !alive(p); }, 3)) << "orphan " << p;
  const std::string out = l.output();
  EXPECT_NE(out.find("deaf: still running after the grace period, SIGKILL"), std::string::npos)
      << out;
  // Reverse order: deaf (started last) first, a last.
  EXPECT_LT(out.find("deaf stopped"), out.find("b stopped"));
  EXPECT_LT(out.find("b stopped"), out.find("a stopped"));
  EXPECT_NE(out.find("stopping: SIGTERM"), std::string::npos);
}

TEST(LaunchProcess, ChildrenDieWithAKilledLauncher) {
  Launcher l("name: t\nroot: .\nlogger: {enabled: false}\nprocesses:\n" + sleeper("a"));
  ASSERT_TRUE(wait_for([&] { return read_pid(l.dir / "a.pid") > 0; }));
  ASSERT_TRUE(wait_for([&] { return read_pid(l.dir / "a.child") > 0; }));
  const int a = read_pid(l.dir / "a.pid");
  const int grandchild = read_pid(l.dir / "a.child");  // sh's background sleep
  ASSERT_TRUE(alive(grandchild));
  ::kill(l.pid, SIGKILL);
  l.wait_exit();
  EXPECT_TRUE(wait_for([&] { return !alive(a); }, 3));  // PR_SET_PDEATHSIG
  // Not covered by PDEATHSIG: the launcher's guard kills the child's process group.
  EXPECT_TRUE(wait_for([&] { return !alive(grandchild); }, 3)) << "grandchild " << grandchild;
}

TEST(LaunchProcess, EndsWithGivesTheRunsExitStatusAndBadFileGivesTwo) {
  {
    Launcher l("name: t\nroot: .\nends_with: m\nlogger: {enabled: false}\nprocesses:\n" +
               sleeper("a") + "  - {name: m, command: sh, args: [-c, 'sleep 0.3; exit 5']}\n");
    EXPECT_EQ(l.wait_exit(), kExitRunFailed);
    EXPECT_NE(l.output().find("the run ended: m exit 5"), std::string::npos) << l.output();
  }
  {
    Launcher l(
        "name: t\nroot: .\nlogger: {enabled: false}\nprocesses:\n  - {name: m, command: "
        "no-such-program-xyz}\n");
    EXPECT_EQ(l.wait_exit(), kExitUsage);
  }
}

}  // namespace
}  // namespace tiller::launch
