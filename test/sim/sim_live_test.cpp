// tiller-sim as a real process over LCM, inside the private network namespace tools/netns-run
// makes: ESC output (int16 throttle, as tiller-esc's sim backend sends it) drives the Otter
// forward; odometry, ground truth, sim state and the heartbeat arrive; when the ESC output
// stops, the thrust decays to zero; SIGTERM exits 0; a missing vehicle file exits 2 naming it.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tiller/esc_output_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/sim_state_t.hpp>

#include "core/angles.hpp"
#include "runtime/channels.hpp"
#include "runtime/live.hpp"

namespace tiller {
namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";
const std::string kSrc = TILLER_SOURCE_DIR;
const std::string kBin = std::string(TILLER_BIN_DIR) + "/tiller-sim";

struct Proc {
  pid_t pid = -1;
  std::string err;
  explicit Proc(const std::vector<std::string>& args) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("tiller_sim_live_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    err = (dir / "stderr").string();
    pid = fork();
    if (pid == 0) {
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(e, 2);
      std::vector<std::string> all = {kBin};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (auto& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(kBin.c_str(), argv.data());
      _exit(127);
    }
  }
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
  std::string stderr_text() const {
    std::ifstream f(err);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  ~Proc() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

struct Listener {
  std::vector<odometry_t> odom, truth;
  std::vector<sim_state_t> state;
  std::vector<heartbeat_t> beats;
  void on_odom(const lcm::ReceiveBuffer*, const std::string& ch, const odometry_t* m) {
    (ch == channels::kOdometry ? odom : truth).push_back(*m);
  }
  void on_state(const lcm::ReceiveBuffer*, const std::string&, const sim_state_t* m) {
    state.push_back(*m);
  }
  void on_beat(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) {
    beats.push_back(*m);
  }
};

esc_output_t full_ahead(std::int64_t utime, std::int32_t value) {
  esc_output_t m{};
  m.utime = utime;
  m.backend = "sim";
  m.armed = true;
  m.unit = esc_output_t::UNIT_THROTTLE_INT16;
  m.n_channels = 2;
  m.names = {"port", "starboard"};
  m.channel = {0, 1};
  m.value = {value, value};
  m.normalized = {value / 32767.0, value / 32767.0};
  return m;
}

// Publishes `value` every 10 ms for `seconds` (value < 0: publishes nothing) while listening.
void pump(lcm::LCM& lcm, double seconds, std::int32_t value) {
  const auto start = std::chrono::steady_clock::now();
  auto next = start;
  while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
    if (value >= 0 && std::chrono::steady_clock::now() >= next) {
      const auto m = full_ahead(wall_time_us(), value);  // unstamped would be stale
      lcm.publish(channels::kEscOutput, &m);
      next += std::chrono::milliseconds(10);
    }
    lcm.handleTimeout(2);
  }
}

TEST(SimLive, OdometryUnderLcmAndThrustDecaysWhenEscOutputStops) {
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  Listener l;
  lcm.subscribe(channels::kOdometry, &Listener::on_odom, &l);
  lcm.subscribe(channels::kGroundTruth, &Listener::on_odom, &l);
  lcm.subscribe(channels::kSimState, &Listener::on_state, &l);
  lcm.subscribe("TILLER_HEARTBEAT_SIM", &Listener::on_beat, &l);
  Proc sim({"--vehicle", kSrc + "/config/vehicles/otter.yaml", "--lcm-url", kUrl, "--north", "5",
            "--heading-deg", "90"});
  pump(lcm, 3.0, 32767);
  ASSERT_GE(l.odom.size(), 10u) << sim.stderr_text();
  ASSERT_GE(l.truth.size(), 10u);
  ASSERT_FALSE(l.state.empty());
  ASSERT_FALSE(l.beats.empty());
  EXPECT_EQ(l.beats.back().process, "sim");
  const auto& o = l.odom.back();
  // Heading east from (5, 0): moves east, north stays 5; surging ahead at full thrust.
  EXPECT_NEAR(o.orientation[2], kPi / 2, 1e-9);
  EXPECT_NEAR(o.position[0], 5.0, 1e-6);
  EXPECT_GT(o.position[1], 1.0);
  EXPECT_GT(o.velocity[0], 1.0);
  EXPECT_NEAR(l.state.back().thrust[0], 119.7, 1.0);
  // ESC output stops: after the 0.5 s timeout the thrust decays with the 0.1 s lag.
  pump(lcm, 2.0, -1);
  ASSERT_FALSE(l.state.empty());
  EXPECT_LT(std::abs(l.state.back().thrust[0]), 1.0);
  EXPECT_EQ(l.beats.back().state, heartbeat_t::STATE_DEGRADED);
  kill(sim.pid, SIGTERM);
  EXPECT_EQ(sim.wait(5.0), 0);
}

// Issue 13, finding 5: a mission file's start: is where a simulated run starts. tiller-sim
// --mission FILE (the launch files pass the mission they fly) starts the boat there; the pose
// flags still win over it; a mission without start: (CSV) leaves the config's pose. (Before:
// --mission was an unknown option, and the launch file started every mission at the config's
// pose.)
TEST(SimLive, MissionStartIsWhereTheBoatStarts) {
  const auto dir = std::filesystem::temp_directory_path() / "tiller-sim-live-test";
  std::filesystem::create_directories(dir);
  const std::string mission = (dir / "start.yaml").string();
  std::ofstream(mission) << "name: start\nstart: {north: 7, east: -4, heading_deg: 45}\n"
                            "waypoints:\n  - [7, -4]\n  - [20, -4]\n";
  const auto first_pose = [&](const std::vector<std::string>& extra) {
    lcm::LCM lcm(kUrl);
    Listener l;
    lcm.subscribe(channels::kOdometry, &Listener::on_odom, &l);  // no noise in sim.yaml
    std::vector<std::string> args = {"--vehicle", kSrc + "/config/vehicles/otter.yaml", "--lcm-url",
                                     kUrl};
    args.insert(args.end(), extra.begin(), extra.end());
    Proc sim(args);
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (l.odom.size() < 2 && std::chrono::steady_clock::now() < end) lcm.handleTimeout(10);
    kill(sim.pid, SIGTERM);
    EXPECT_EQ(sim.wait(5.0), 0) << sim.stderr_text();
    return l.odom.empty() ? odometry_t{} : l.odom.front();
  };
  auto o = first_pose({"--mission", mission});
  EXPECT_NEAR(o.position[0], 7.0, 1e-6);
  EXPECT_NEAR(o.position[1], -4.0, 1e-6);
  EXPECT_NEAR(o.orientation[2], kPi / 4, 1e-9);
  o = first_pose({"--mission", mission, "--east", "2"});  // a flag wins over the mission
  EXPECT_NEAR(o.position[0], 7.0, 1e-6);
  EXPECT_NEAR(o.position[1], 2.0, 1e-6);
  o = first_pose({"--mission", kSrc + "/config/missions/wayfinding.csv", "--north", "1"});
  EXPECT_NEAR(o.position[0], 1.0, 1e-6);  // CSV: no start:, the config's pose (east 0)
  EXPECT_NEAR(o.position[1], 0.0, 1e-6);
  Proc missing({"--mission", "config/missions/no_such_mission.yaml", "--lcm-url", kUrl});
  EXPECT_EQ(missing.wait(5.0), 2);
  EXPECT_NE(missing.stderr_text().find("no_such_mission.yaml"), std::string::npos)
      << missing.stderr_text();
}

TEST(SimLive, EveryVehicleFileRunsAndPublishesOdometry) {
  std::vector<std::string> vehicles;  // every shipped file, so a new one is covered
  for (const auto& e : std::filesystem::directory_iterator(kSrc + "/config/vehicles")) {
    if (e.path().extension() == ".yaml") vehicles.push_back(e.path().stem().string());
  }
  ASSERT_GE(vehicles.size(), 7u);
  for (const std::string& v : vehicles) {
    lcm::LCM lcm(kUrl);
    ASSERT_TRUE(lcm.good());
    Listener l;
    lcm.subscribe(channels::kOdometry, &Listener::on_odom, &l);
    Proc sim({"--vehicle", kSrc + "/config/vehicles/" + v + ".yaml", "--lcm-url", kUrl});
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (l.odom.size() < 3 && std::chrono::steady_clock::now() < end) lcm.handleTimeout(10);
    EXPECT_GE(l.odom.size(), 3u) << v << ": " << sim.stderr_text();
    kill(sim.pid, SIGTERM);
    EXPECT_EQ(sim.wait(5.0), 0) << v;
  }
}

TEST(SimLive, MissingVehicleFileExitsWithTheFileName) {
  Proc sim({"--vehicle", "config/vehicles/no_such_boat.yaml", "--lcm-url", kUrl});
  EXPECT_EQ(sim.wait(5.0), 2);
  EXPECT_NE(sim.stderr_text().find("no_such_boat.yaml"), std::string::npos) << sim.stderr_text();
}

// Every bad flag is refused before LCM is opened: exit 2, naming the flag, what was expected
// (the config's range for the same setting) and the value given.
TEST(SimLive, BadFlagsExitTwoNamingTheFlagTheRangeAndTheValue) {
  struct Case {
    std::vector<std::string> args;
    std::string flag, expected, value;
  };
  const std::vector<Case> cases = {
      {{"--north", "inf"}, "--north", "[-1e+06, 1e+06]", "'inf'"},
      {{"--east", "-1e7"}, "--east", "[-1e+06, 1e+06]", "'-1e7'"},
      {{"--north", "1x"}, "--north", "finite number", "'1x'"},
      {{"--north", " 1"}, "--north", "finite number", "' 1'"},
      {{"--heading-deg", "nan"}, "--heading-deg", "[-360, 360]", "'nan'"},
      {{"--heading-deg", "400"}, "--heading-deg", "[-360, 360]", "'400'"},
      {{"--current-speed", "-1"}, "--current-speed", "[0, 5]", "'-1'"},
      {{"--current-speed", "9"}, "--current-speed", "[0, 5]", "'9'"},
      {{"--current-speed", "0.3", "--current-toward-deg", "north"},
       "--current-toward-deg",
       "[-360, 360]",
       "'north'"},
      {{"--current-toward-deg", "30"}, "--current-toward-deg", "--current-speed", "'30'"},
      {{"--seed", "-3"}, "--seed", "integer in [0,", "'-3'"},
      {{"--seed", "1.5"}, "--seed", "integer in [0,", "'1.5'"},
      {{"--seed", "99999999999999999999"}, "--seed", "integer in [0,", "'99999999999999999999'"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> args = c.args;
    args.insert(args.end(), {"--vehicle", kSrc + "/config/vehicles/otter.yaml", "--lcm-url", kUrl});
    Proc sim(args);
    const int rc = sim.wait(5.0);
    const std::string err = sim.stderr_text();
    SCOPED_TRACE(c.args[0] + " " + c.args[1] + ": " + err);
    EXPECT_EQ(rc, 2);
    EXPECT_NE(err.find(c.flag + ":"), std::string::npos);
    EXPECT_NE(err.find(c.expected), std::string::npos);
    EXPECT_NE(err.find("got " + c.value), std::string::npos);
    EXPECT_EQ(err.find("tiller-sim: otter"), std::string::npos);  // never started
  }
  // The good values of the same flags start it (and it stops cleanly on SIGTERM).
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  Listener l;
  lcm.subscribe(channels::kOdometry, &Listener::on_odom, &l);
  Proc sim({"--vehicle", kSrc + "/config/vehicles/otter.yaml", "--lcm-url", kUrl, "--north",
            "-12.5", "--east", "1e3", "--heading-deg", "-90", "--current-speed", "0.5",
            "--current-toward-deg", "90", "--seed", "3"});
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (l.odom.size() < 3 && std::chrono::steady_clock::now() < end) lcm.handleTimeout(10);
  ASSERT_GE(l.odom.size(), 3u) << sim.stderr_text();
  EXPECT_NEAR(l.odom.back().position[0], -12.5, 1e-6);
  EXPECT_GT(l.odom.back().position[1], 1e3);  // drifting east with the current
  EXPECT_NEAR(l.odom.back().orientation[2], -kPi / 2, 1e-6);
  kill(sim.pid, SIGTERM);
  EXPECT_EQ(sim.wait(5.0), 0);
}

}  // namespace
}  // namespace tiller
