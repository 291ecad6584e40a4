// tiller-mixer as a real process over LCM (inside the private namespace tools/netns-run
// makes): neutral and disarmed until an arm state says armed, then commands that follow the
// manual demand; thruster commands and allocation status visible on the bus; bad config exits 2
// naming the key.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/live.hpp"

namespace tiller {
namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
const std::string kSrc = TILLER_SOURCE_DIR;
const std::string kBin = std::string(TILLER_BIN_DIR) + "/tiller-mixer";

pid_t spawn(const std::vector<std::string>& args, const std::string& err_file) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (FILE* f = std::freopen(err_file.c_str(), "w", stderr)) (void)f;
    std::vector<std::string> all = {kBin};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(kBin.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

int wait_exit(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid)
      return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

struct Rx {
  void on_cmd(const lcm::ReceiveBuffer*, const std::string&, const thruster_command_t* m) {
    ++commands;
    last = *m;
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const allocation_status_t* m) {
    ++statuses;
    status = *m;
  }
  int commands = 0, statuses = 0;
  thruster_command_t last{};
  allocation_status_t status{};
};

bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds,
                const std::function<void()>& each) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    each();
    l.handleTimeout(10);
  }
  return pred();
}

TEST(MixerApp, FollowsTheStickOnceArmedOverLcm) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good());
  Rx rx;
  l.subscribe(channels::kThrusterCommand, &Rx::on_cmd, &rx);
  l.subscribe(channels::kAllocationStatus, &Rx::on_status, &rx);
  const std::string err =
      (std::filesystem::temp_directory_path() / "tiller_mixer_app.err").string();
  const pid_t pid =
      spawn({"--config", kSrc + "/config/mixer/seed001_rov6.yaml", "--lcm-url", kUrl}, err);
  // Disarmed: commands flow, all neutral.
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.commands >= 5; }, 10.0, [] {}));
  EXPECT_FALSE(rx.last.armed);
  ASSERT_EQ(rx.last.n_thrusters, 6);
  for (double c : rx.last.command) EXPECT_EQ(c, 0.0);
  // Arm (as tiller-esc would), the stick centred for the first feeds (the safety gate's start
  // condition, docs/safety.md), then forward.
  int feeds = 0;
  auto feed = [&] {
    arm_state_t a{};
    a.utime = wall_time_us();  // stamped as a sender does: an unstamped message is stale
    a.armed = true;
    a.reason = "test";
    l.publish(channels::kArmState, &a);
    manual_demand_t m{};
    m.utime = wall_time_us();
    m.demand[0] = ++feeds > 5 ? 0.5 : 0.0;
    m.valid = true;
    l.publish(channels::kManualDemand, &m);
  };
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last.armed && rx.last.command[1] > 0.1; }, 10.0, feed));
  EXPECT_EQ(rx.last.source, 1);
  EXPECT_EQ(rx.last.names[1], "LF");
  // Forward: the four vectored thrusters all push, F and B hold the pitch.
  for (int i : {1, 2, 4, 5}) EXPECT_GT(rx.last.command[static_cast<std::size_t>(i)], 0.1);
  EXPECT_GT(rx.statuses, 0);
  EXPECT_EQ(rx.status.strategy, "direction_preserving");
  EXPECT_TRUE(rx.status.axis_unactuated[3]);  // no roll authority
  kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 10.0), 0);
}

TEST(MixerApp, BadConfigExitsTwoNamingTheKey) {
  const auto dir = std::filesystem::temp_directory_path();
  const std::string cfg = (dir / "tiller_mixer_bad.yaml").string();
  std::ofstream(cfg) << "vehicle: ../vehicles/otter.yaml\nrate_hz: -3\n";
  const std::string err = (dir / "tiller_mixer_bad.err").string();
  const pid_t pid = spawn({"--config", cfg, "--lcm-url", kUrl}, err);
  EXPECT_EQ(wait_exit(pid, 10.0), 2);
  std::ifstream f(err);
  std::stringstream s;
  s << f.rdbuf();
  EXPECT_NE(s.str().find("vehicle"), std::string::npos) << s.str();
}

}  // namespace
}  // namespace tiller
