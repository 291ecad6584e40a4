// tiller-esc as a real process over LCM, inside the private network namespace tools/netns-run
// makes: the dry-run seed-000 preset arms on request, writes the commanded throttle bytes, and
// on SIGTERM writes neutral to every ESC and exits 0; a missing ESC with missing_esc: refuse
// stops it with a clear message; degraded runs; a bad config names the file and key.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "runtime/channels.hpp"
#include "runtime/live.hpp"

namespace tiller {
namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
const std::string kSrc = TILLER_SOURCE_DIR;
const std::string kBin = std::string(TILLER_BIN_DIR) + "/tiller-esc";

struct Proc {
  pid_t pid = -1;
  std::string out, err;  // files holding its stdout and stderr
  Proc(const std::vector<std::string>& args, const std::string& tag) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("tiller_esc_app_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    out = (dir / (tag + ".out")).string();
    err = (dir / (tag + ".err")).string();
    pid = fork();
    if (pid == 0) {
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(o, 1);
      dup2(e, 2);
      std::vector<char*> argv;
      std::vector<std::string> all = {kBin};
      all.insert(all.end(), args.begin(), args.end());
      for (auto& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(kBin.c_str(), argv.data());
      _exit(127);
    }
  }
  // Exit status, or -1 if it did not exit within `seconds`.
  int wait(double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      int st = 0;
      if (waitpid(pid, &st, WNOHANG) == pid) {
        pid = -1;
        return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return -1;
  }
  ~Proc() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Rx {
  void on_output(const lcm::ReceiveBuffer*, const std::string&, const esc_output_t* m) {
    ++outputs;
    last_output = *m;
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) {
    last_arm = *m;
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const esc_bus_status_t* m) {
    ++statuses;
    last_status = *m;
  }
  int outputs = 0, statuses = 0;
  esc_output_t last_output{};
  arm_state_t last_arm{};
  esc_bus_status_t last_status{};
};

bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds,
                const std::function<void()>& each = {}) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    if (each) each();
    l.handleTimeout(10);
  }
  return pred();
}

std::string temp_config(const std::string& name, const std::string& text) {
  const auto p =
      std::filesystem::temp_directory_path() / (name + std::to_string(getpid()) + ".yaml");
  std::ofstream(p) << text;
  return p.string();
}

TEST(EscApp, DryRunArmsWritesAndWritesNeutralOnSigterm) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "LCM not available: is this test running under tools/netns-run?";
  Rx rx;
  l.subscribe(channels::kEscOutput, &Rx::on_output, &rx);
  l.subscribe(channels::kArmState, &Rx::on_arm, &rx);
  l.subscribe(channels::kEscStatus, &Rx::on_status, &rx);
  Proc esc({"--config", kSrc + "/config/esc/seed000_dry_run.yaml", "--lcm-url", kUrl}, "dry");
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.outputs > 5; }, 10.0))
      << slurp(esc.err);
  EXPECT_FALSE(rx.last_output.armed);
  EXPECT_EQ(rx.last_output.backend, "dry_run");

  thruster_command_t cmd{};
  cmd.armed = false;
  cmd.arm_allowed = true;
  cmd.n_thrusters = 4;
  cmd.names = {"t1", "t2", "t3", "t4"};
  cmd.command = {0, 0, 0, 0};
  auto send = [&] {
    cmd.utime = wall_time_us();
    l.publish(channels::kThrusterCommand, &cmd);
  };
  send();
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_arm.boot_nonce != 0; }, 5.0, send))
      << "tiller-esc announces a random boot nonce";
  // An arm request without it (or with another start's) is refused and says why.
  arm_request_t arm{};
  arm.utime = wall_time_us();
  arm.arm = true;
  arm.source = "app_test";
  arm.boot_nonce = rx.last_arm.boot_nonce + 1;
  l.publish(channels::kArmRequest, &arm);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_arm.reason.find("boot nonce differs") != std::string::npos; }, 5.0,
      send));
  EXPECT_FALSE(rx.last_arm.armed);
  arm.utime = wall_time_us();
  arm.boot_nonce = rx.last_arm.boot_nonce;
  l.publish(channels::kArmRequest, &arm);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_arm.armed; }, 5.0, send));
  EXPECT_EQ(rx.last_arm.reason, "armed by app_test");

  cmd.armed = true;
  cmd.command = {0.5, -1.0, 0.25, 0.0};
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_output.armed && rx.last_output.value[0] == 16384; }, 5.0, send));
  EXPECT_EQ(rx.last_output.value, (std::vector<std::int32_t>{16384, -32767, 8192, 0}));
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.statuses > 0; }, 2.0, send));
  EXPECT_EQ(rx.last_status.n_escs, 4);
  EXPECT_EQ(rx.last_status.bus, "dry-run");

  // SIGTERM while the thrusters run.
  send();
  ASSERT_EQ(kill(esc.pid, SIGTERM), 0);
  EXPECT_EQ(esc.wait(5.0), 0) << slurp(esc.err);
  pump_until(
      l, [] { return false; }, 0.2);
  EXPECT_FALSE(rx.last_output.armed);
  EXPECT_EQ(rx.last_output.value, (std::vector<std::int32_t>{0, 0, 0, 0}));
  EXPECT_FALSE(rx.last_arm.armed);

  // What went on the (dry-run) bus: the commanded bytes, and neutral last for every ESC.
  const std::string out = slurp(esc.out);
  EXPECT_NE(out.find("0x29 write 00 40 00"), std::string::npos) << out;
  EXPECT_NE(out.find("0x2a write 00 80 01"), std::string::npos) << out;
  for (const char* a : {"0x29", "0x2a", "0x2b", "0x2c"}) {
    const auto last = out.rfind(std::string(a) + " write");
    ASSERT_NE(last, std::string::npos) << a;
    EXPECT_EQ(out.substr(last, std::string(a).size() + 15), std::string(a) + " write 00 00 00")
        << a << "\n"
        << out;
  }
}

std::string dry_with(const std::string& policy) {
  return "vehicle: " + kSrc +
         "/config/vehicles/seed000_rov4.yaml\n"
         "backend: dry_run\nmissing_esc: " +
         policy +
         "\n"
         "dry_run: {protocol: i2c_tgy, unplugged: [0x2b]}\n"
         "escs:\n  - {name: t1, address: 0x29}\n  - {name: t2, address: 0x2a}\n"
         "  - {name: t3, address: 0x2b}\n  - {name: t4, address: 0x2c}\n";
}

TEST(EscApp, MissingEscRefusesWithAClearMessage) {
  Proc esc({"--config", temp_config("refuse", dry_with("refuse")), "--lcm-url", kUrl}, "refuse");
  EXPECT_EQ(esc.wait(10.0), 2);
  const std::string err = slurp(esc.err);
  EXPECT_NE(err.find("ESC t3: nothing at 0x2b on dry-run: ENXIO"), std::string::npos) << err;
  EXPECT_NE(err.find("refusing to start"), std::string::npos) << err;
  // The ESCs that did answer got neutral before the exit.
  const std::string out = slurp(esc.out);
  EXPECT_NE(out.rfind("0x29 write 00 00 00"), std::string::npos) << out;
}

TEST(EscApp, MissingEscDegradedKeepsRunning) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good());
  Rx rx;
  l.subscribe(channels::kEscStatus, &Rx::on_status, &rx);
  Proc esc({"--config", temp_config("degraded", dry_with("degraded")), "--lcm-url", kUrl},
           "degraded");
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.statuses > 2; }, 10.0))
      << slurp(esc.err);
  EXPECT_EQ(rx.last_status.present, (std::vector<std::int8_t>{1, 1, 0, 1}));
  EXPECT_GT(rx.last_status.write_errors[2], 0);
  EXPECT_EQ(rx.last_status.last_errno[2], ENXIO);
  EXPECT_NE(slurp(esc.err).find("running degraded"), std::string::npos);
  kill(esc.pid, SIGINT);
  EXPECT_EQ(esc.wait(5.0), 0);
}

TEST(EscApp, BadConfigNamesFileAndKey) {
  const std::string cfg = temp_config("bad", dry_with("refuse") + "comand_timeout_ms: 100\n");
  Proc esc({"--config", cfg, "--lcm-url", kUrl}, "bad");
  EXPECT_EQ(esc.wait(10.0), 2);
  const std::string err = slurp(esc.err);
  EXPECT_NE(err.find(cfg), std::string::npos) << err;
  EXPECT_NE(err.find("comand_timeout_ms: unknown key"), std::string::npos) << err;
}

TEST(EscApp, HardwarePresetWithoutTheBusSaysSo) {
  Proc esc({"--config", kSrc + "/config/esc/seed000_i2c.yaml", "--lcm-url", kUrl}, "nobus");
  EXPECT_EQ(esc.wait(10.0), 2);
  const std::string err = slurp(esc.err);
  EXPECT_NE(err.find("cannot open I2C bus /dev/i2c-1"), std::string::npos) << err;
}

}  // namespace
}  // namespace tiller
