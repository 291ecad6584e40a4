// Real time through the real kernel and the real programs (runtime/realtime.hpp), in two CTest
// entries of this one binary:
//   realtime_refused_test  under tools/netns-run (a user namespace: the kernel refuses
//                          SCHED_FIFO with EPERM): tiller-esc warns, naming what is missing
//                          and how to grant it, keeps running and says realtime.refused = 1 in
//                          its heartbeat; --realtime-required and the launch file's
//                          required: true refuse to start (exit 2);
//   realtime_granted_test  under tools/netns-run --root (real root, no user namespace; skipped
//                          with exit 77 otherwise): a launch file's realtime: entries give
//                          tiller-esc and tiller-mixer SCHED_FIFO at their priorities and
//                          locked memory, as the kernel (/proc) and the heartbeats tell.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tiller/heartbeat_t.hpp>

namespace {

namespace fs = std::filesystem;
constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
const std::string kBin = TILLER_BIN_DIR, kSrc = TILLER_SOURCE_DIR;

std::int64_t now_ms() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(steady_clock::now().time_since_epoch()).count();
}

bool in_user_namespace() {
  std::ifstream in("/proc/self/uid_map");
  long long a = -1, b = -1, c = -1;
  in >> a >> b >> c;
  return !(a == 0 && b == 0 && c == 4294967295LL);
}

// exe args..., stdout and stderr into `out`; dies with this process.
pid_t spawn(const std::string& exe, const std::vector<std::string>& args, const std::string& out) {
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> argv{const_cast<char*>(exe.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Exit status within `seconds`, or -1 (still running).
int wait_exit(pid_t pid, double seconds) {
  const std::int64_t end = now_ms() + static_cast<std::int64_t>(seconds * 1000);
  int status = 0;
  while (now_ms() < end) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return -1;
}

void stop(pid_t pid) {
  kill(pid, SIGTERM);
  if (wait_exit(pid, 10) < 0) kill(pid, SIGKILL), waitpid(pid, nullptr, 0);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last heartbeat counters of each process, by heartbeat channel.
struct Heartbeats {
  std::map<std::string, std::map<std::string, std::int64_t>> counters;
  void on(const lcm::ReceiveBuffer*, const std::string& channel, const tiller::heartbeat_t* m) {
    auto& c = counters[channel];
    for (int i = 0; i < m->n_counters; ++i) c[m->counter_names[i]] = m->counter_values[i];
  }
  bool has(const std::string& channel, const std::string& counter) const {
    auto it = counters.find(channel);
    return it != counters.end() && it->second.count(counter) > 0;
  }
  std::int64_t at(const std::string& channel, const std::string& counter) const {
    return counters.at(channel).at(counter);
  }
};

// Listens until every (channel, counter) pair was heard, or `seconds` pass.
bool hear(lcm::LCM& l, const std::vector<std::pair<std::string, std::string>>& want, double seconds,
          Heartbeats& hb) {
  const std::int64_t end = now_ms() + static_cast<std::int64_t>(seconds * 1000);
  auto all = [&] {
    for (const auto& [ch, c] : want)
      if (!hb.has(ch, c)) return false;
    return true;
  };
  while (!all() && now_ms() < end) l.handleTimeout(50);
  return all();
}

std::string tmp_path(const std::string& name) {
  return (fs::temp_directory_path() / ("tiller_rt_" + std::to_string(getpid()) + "_" + name))
      .string();
}

// A launch file with tiller-esc (sim backend) and tiller-mixer and the given realtime: entries.
std::string write_launch(const std::string& esc_rt, const std::string& mixer_rt) {
  const std::string path = tmp_path("launch.yaml");
  std::ofstream f(path);
  f << "name: rt-test\nroot: " << kSrc << "\nlcm_url: " << kUrl
    << "\ngrace_s: 2\nlogger: {enabled: false}\nprocesses:\n"
    << "  - {name: esc, command: tiller-esc, args: [--config, config/esc/seed000_sim.yaml],"
       " critical: true, realtime: "
    << esc_rt << "}\n"
    << "  - {name: mixer, command: tiller-mixer, args: [--config, "
       "config/mixer/seed000_rov4.yaml], depends_on: [esc], realtime: "
    << mixer_rt << "}\n";
  return path;
}

// ---- realtime_refused_test (tools/netns-run: a user namespace)

TEST(RealtimeRefused, WarnsKeepsRunningAndSaysSoInTheHeartbeat) {
  if (!in_user_namespace()) GTEST_SKIP() << "not in a user namespace: run under tools/netns-run";
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good());
  Heartbeats hb;
  l.subscribe("TILLER_HEARTBEAT_ESC", &Heartbeats::on, &hb);
  const std::string out = tmp_path("esc.out");
  const pid_t esc = spawn(kBin + "/tiller-esc",
                          {"--config", kSrc + "/config/esc/seed000_sim.yaml", "--lcm-url", kUrl,
                           "--realtime-priority", "45", "--lock-memory"},
                          out);
  const bool heard = hear(l, {{"TILLER_HEARTBEAT_ESC", "realtime.refused"}}, 10, hb);
  EXPECT_EQ(wait_exit(esc, 0.2), -1) << "tiller-esc stopped:\n" << slurp(out);
  EXPECT_EQ(sched_getscheduler(esc), SCHED_OTHER);
  stop(esc);
  const std::string said = slurp(out);
  ASSERT_TRUE(heard) << said;
  EXPECT_EQ(hb.at("TILLER_HEARTBEAT_ESC", "realtime.refused"), 1);
  EXPECT_EQ(hb.at("TILLER_HEARTBEAT_ESC", "realtime.priority"), 0);
  EXPECT_EQ(hb.at("TILLER_HEARTBEAT_ESC", "realtime.locked"), 0);
  for (const char* part :
       {"tiller-esc: warning: real time: SCHED_FIFO priority 45 refused (EPERM)",
        "RLIMIT_RTPRIO >= 45", "LimitRTPRIO=45", "user namespace",
        "tiller-esc: warning: real time: memory not locked", "LimitMEMLOCK=infinity",
        "tiller-esc: real time: normal scheduler, memory not locked (continuing"}) {
    EXPECT_NE(said.find(part), std::string::npos) << "missing: " << part << "\n" << said;
  }
}

TEST(RealtimeRefused, RequiredRefusesToStartWithExitTwo) {
  if (!in_user_namespace()) GTEST_SKIP() << "not in a user namespace: run under tools/netns-run";
  const std::string out = tmp_path("mixer.out");
  const pid_t mixer = spawn(kBin + "/tiller-mixer",
                            {"--config", kSrc + "/config/mixer/seed000_rov4.yaml", "--lcm-url",
                             kUrl, "--realtime-priority=40", "--realtime-required"},
                            out);
  EXPECT_EQ(wait_exit(mixer, 10), 2);
  const std::string said = slurp(out);
  EXPECT_NE(said.find("tiller-mixer: error: real time: SCHED_FIFO priority 40 refused (EPERM)"),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("tiller-mixer: not starting: real time is required"), std::string::npos)
      << said;
}

TEST(RealtimeRefused, LaunchFileRequiredEndsTheRunWithTheReason) {
  if (!in_user_namespace()) GTEST_SKIP() << "not in a user namespace: run under tools/netns-run";
  const std::string lf = write_launch("{priority: 45, required: true}", "{priority: 40}");
  const std::string out = tmp_path("launch.out");
  const pid_t check = spawn(kBin + "/tiller-launch", {"--check", lf}, out);
  EXPECT_EQ(wait_exit(check, 20), 0) << slurp(out);
  const std::string plan = slurp(out);
  EXPECT_NE(plan.find("tiller-esc --config config/esc/seed000_sim.yaml --realtime-priority=45 "
                      "--lock-memory --realtime-required"),
            std::string::npos)
      << plan;
  const pid_t launch = spawn(kBin + "/tiller-launch", {lf}, out);
  const int rc = wait_exit(launch, 20);
  if (rc < 0) stop(launch);
  const std::string said = slurp(out);
  EXPECT_EQ(rc, 3) << said;  // esc (critical, restart never) failed
  EXPECT_NE(said.find("tiller-esc: not starting: real time is required"), std::string::npos)
      << said;
  EXPECT_NE(said.find("exit 2"), std::string::npos) << said;
  fs::remove(lf);
}

// ---- realtime_granted_test (tools/netns-run --root: real root)

// Children of `parent` by program name (from /proc).
std::map<std::string, pid_t> children_of(pid_t parent) {
  std::map<std::string, pid_t> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream st(e.path() / "stat");
    std::string stat;
    std::getline(st, stat);
    const auto close = stat.rfind(')');
    const auto open = stat.find('(');
    if (close == std::string::npos || open == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 2));
    char state = 0;
    pid_t ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent) out[stat.substr(open + 1, close - open - 1)] = std::stoi(name);
  }
  return out;
}

long vm_locked_kb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

TEST(RealtimeGranted, LaunchFileGivesEscAndMixerFifoAndLockedMemory) {
  if (getuid() != 0 || in_user_namespace())
    GTEST_SKIP() << "needs real root outside a user namespace (tools/netns-run --root)";
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good());
  Heartbeats hb;
  l.subscribe("TILLER_HEARTBEAT_.*", &Heartbeats::on, &hb);
  const std::string lf = write_launch("{priority: 45, required: true}", "{priority: 40}");
  const std::string out = tmp_path("launch.out");
  const pid_t launch = spawn(kBin + "/tiller-launch", {lf}, out);
  const bool heard = hear(l,
                          {{"TILLER_HEARTBEAT_ESC", "realtime.priority"},
                           {"TILLER_HEARTBEAT_MIXER", "realtime.priority"}},
                          15, hb);
  const auto kids = children_of(launch);
  std::map<std::string, int> policy, priority;
  std::map<std::string, long> locked_kb;
  for (const auto& [name, pid] : kids) {
    sched_param sp{};
    sched_getparam(pid, &sp);
    policy[name] = sched_getscheduler(pid);
    priority[name] = sp.sched_priority;
    locked_kb[name] = vm_locked_kb(pid);
  }
  stop(launch);
  const std::string said = slurp(out);
  ASSERT_TRUE(heard) << said;
  for (const auto& [name, prio] :
       {std::pair<std::string, int>{"tiller-esc", 45}, {"tiller-mixer", 40}}) {
    ASSERT_TRUE(kids.count(name)) << name << " not running under the launcher\n" << said;
    EXPECT_EQ(policy[name], SCHED_FIFO) << name;
    EXPECT_EQ(priority[name], prio) << name;
    EXPECT_GT(locked_kb[name], 1000) << name << ": VmLck " << locked_kb[name] << " kB";
  }
  for (const auto& [ch, prio] :
       {std::pair<std::string, int>{"TILLER_HEARTBEAT_ESC", 45}, {"TILLER_HEARTBEAT_MIXER", 40}}) {
    EXPECT_EQ(hb.at(ch, "realtime.priority"), prio) << ch;
    EXPECT_EQ(hb.at(ch, "realtime.locked"), 1) << ch;
    EXPECT_EQ(hb.at(ch, "realtime.refused"), 0) << ch;
  }
  EXPECT_NE(said.find("tiller-esc: real time: SCHED_FIFO priority 45, memory locked"),
            std::string::npos)
      << said;
  fs::remove(lf);
}

}  // namespace
