// The shipped launch files (config/launch/): each loads and passes `tiller-launch --check`, the
// logger's command line from the file, autostart, and what the vehicle files run (the real USV
// never arms at a plain start; every vehicle file runs the failsafe on sensors).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "launch/launch_file.hpp"
#include "launch/supervisor.hpp"

namespace fs = std::filesystem;

namespace tiller::launch {
namespace {

// Every shipped launch file loads, passes `tiller-launch --check` (every program exists), and
// every config/... path in its arguments names a file in the tree.
TEST(LaunchFiles, EveryShippedFileChecksAndNamesExistingFiles) {
  const std::string root = TILLER_SOURCE_DIR;
  // Real-vehicle files need their key (/etc/tiller/vehicle.key): give them one, as an operator
  // would with TILLER_KEY_FILE (and the simulator files then do not make keys/sim.key).
  const fs::path key =
      fs::temp_directory_path() / ("tiller-launch-key-" + std::to_string(::getpid()));
  fs::remove(key);
  ASSERT_EQ(
      std::system((std::string(TILLER_BIN_DIR) + "/tiller-key new " + key.string() + " > /dev/null")
                      .c_str()),
      0);
  ::setenv("TILLER_KEY_FILE", key.c_str(), 1);
  int n = 0;
  for (const auto& e : fs::directory_iterator(root + "/config/launch")) {
    if (e.path().extension() != ".yaml") continue;
    ++n;
    SCOPED_TRACE(e.path().string());
    const LaunchFile lf = load_launch_file(e.path().string());
    EXPECT_EQ(fs::canonical(lf.root), fs::canonical(root));
    // Issue 30: every shipped file signs and refuses unsigned input.
    EXPECT_FALSE(lf.key_file.empty());
    EXPECT_TRUE(lf.require_signed);
    EXPECT_FALSE(lf.allow_unsigned);
    for (const auto& p : lf.processes) {
      for (const auto& raw : p.args) {
        const std::string a =
            substitute(raw, {{"LCM_URL", lf.lcm_url}, {"RUN_DIR", "/tmp/tiller-run-XXXXXX"}});
        const auto pos = a.find("config/");
        if (pos == std::string::npos) continue;
        EXPECT_TRUE(fs::exists(root + "/" + a.substr(pos))) << p.name << ": " << a;
      }
    }
    const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-launch --check " +
                            e.path().string() + " > /dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    // Who may command: every shipped file signs; real-vehicle files and the main job's refuse
    // unsigned input (docs/safety.md).
    EXPECT_FALSE(lf.key_file.empty());
    const std::string base = e.path().filename().string();
    if (base.rfind("real_", 0) == 0 || base == "sim_usv_mission.yaml" ||
        base == "sim_usv_sensors.yaml") {
      EXPECT_TRUE(lf.require_signed);
    }
    if (base.rfind("real_", 0) == 0) {
      EXPECT_FALSE(lf.create_key) << "a real vehicle never makes its own key";
    }
  }
  ::unsetenv("TILLER_KEY_FILE");
  fs::remove(key);
  EXPECT_GE(n, 5);
}

}  // namespace
}  // namespace tiller::launch

namespace tiller::launch {
namespace {

// lcm-logger gets the URL as --lcm-url= (1.3.1's -l is broken), last before the file name (given
// before --split-mb it loses the name), and split/rotate from the launch file.
// Issue 33: --check validates a real-vehicle file without creating, moving or removing a file:
// the log directory (with a previous run's .0 in it) is the same afterwards, nothing else made.
TEST(LaunchFiles, CheckCreatesNoFile) {
  const fs::path dir = fs::temp_directory_path() / ("check-no-file-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "logs");
  { std::ofstream(dir / "logs" / "real-bluerov2.lcmlog.0") << "last run"; }
  const fs::path key = dir / "vehicle.key";
  ASSERT_EQ(
      std::system((std::string(TILLER_BIN_DIR) + "/tiller-key new " + key.string() + " > /dev/null")
                      .c_str()),
      0);
  const auto listing = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.push_back(e.path().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const auto before = listing();
  for (const char* file : {"real_bluerov2.yaml", "real_blueboat.yaml", "topside_blueboat.yaml",
                           "topside_bluerov2.yaml"}) {
    const std::string cmd = "TILLER_KEY_FILE=" + key.string() + " " + TILLER_BIN_DIR +
                            "/tiller-launch --check --log-dir " + (dir / "logs").string() + " " +
                            TILLER_SOURCE_DIR + "/config/launch/" + file + " > /dev/null";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << file;
    EXPECT_EQ(listing(), before) << file;
  }
  std::ifstream in(dir / "logs" / "real-bluerov2.lcmlog.0");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "last run");
  fs::remove_all(dir);
}

TEST(LaunchFiles, LoggerCommandLineFromConfig) {
  const fs::path dir =
      fs::temp_directory_path() / ("tiller-logger-args-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "l.yaml") << "name: l\nroot: .\nlcm_url: udpm://239.255.76.67:7667?ttl=0\n"
                                   "logger: {dir: mylogs, split_mb: 2.5, channels: 'TILLER_.*'}\n"
                                   "processes:\n  - {name: a, command: sh}\n";
  const std::string out = (dir / "out.txt").string();
  const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-launch --check " +
                          (dir / "l.yaml").string() + " --log-file " +
                          (dir / "run.lcmlog").string() + " > " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::stringstream ss;
  ss << std::ifstream(out).rdbuf();
  EXPECT_NE(ss.str().find("lcm-logger --quiet --channel=TILLER_.* --split-mb=2.500000 --increment "
                          "--lcm-url=udpm://239.255.76.67:7667?ttl=0 " +
                          (dir / "run.lcmlog").string()),
            std::string::npos)
      << ss.str();
  // split_mb with rotate (bounded): --rotate instead of --increment, and without --log-file a
  // fixed name <dir>/<launch name>.lcmlog so the runs of past boots rotate away too.
  std::ofstream(dir / "r.yaml") << "name: rot\nroot: .\n"
                                   "logger: {dir: mylogs, split_mb: 50, rotate: 20}\n"
                                   "processes:\n  - {name: a, command: sh}\n";
  const std::string cmd2 = std::string(TILLER_BIN_DIR) + "/tiller-launch --check " +
                           (dir / "r.yaml").string() + " > " + out;
  ASSERT_EQ(std::system(cmd2.c_str()), 0);
  std::stringstream s2;
  s2 << std::ifstream(out).rdbuf();
  EXPECT_NE(s2.str().find("--split-mb=50.000000 --rotate=20 --lcm-url="), std::string::npos)
      << s2.str();
  EXPECT_NE(s2.str().find((fs::canonical(dir) / "mylogs" / "rot.lcmlog").string()),
            std::string::npos)
      << s2.str();
  EXPECT_EQ(s2.str().find("--increment"), std::string::npos) << s2.str();
  fs::remove_all(dir);
}

// autostart: false keeps a process out of a plain start; its group or name starts it.
TEST(LaunchFile, AutostartFalseOnlyWhenAskedFor) {
  const auto v = config::Value::parse(
      "name: t\nroot: .\nprocesses:\n  - {name: a, command: sh}\n"
      "  - {name: m, command: sh, group: mission, autostart: false}\n",
      "t.yaml");
  const LaunchFile lf = load_launch(v, ".");
  EXPECT_EQ(select(lf, {}, {}), (std::vector<std::size_t>{0}));
  EXPECT_EQ(select(lf, {"mission"}, {}), (std::vector<std::size_t>{1}));
  EXPECT_EQ(select(lf, {"default", "mission"}, {}), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(select(lf, {}, {"m"}), (std::vector<std::size_t>{1}));
}

// The real USV never arms at a plain start (the boot service): its mission is not started, and
// the plain start runs the localisation chain (issue 14 item 7: no PLACEHOLDER process).
TEST(LaunchFiles, RealUsvMissionIsNotStartedByDefault) {
  const LaunchFile lf =
      load_launch_file(std::string(TILLER_SOURCE_DIR) + "/config/launch/real_usv.yaml");
  std::set<std::string> commands;
  for (std::size_t i : select(lf, {}, {})) {
    EXPECT_NE(lf.processes[i].name, "mission");
    commands.insert(lf.processes[i].command);
  }
  for (const char* c : {"tiller-gnss", "tiller-imu", "tiller-nav", "tiller-power",
                        "tiller-failsafe", "tiller-esc", "tiller-mixer"})
    EXPECT_EQ(commands.count(c), 1u) << c;
  EXPECT_EQ(commands.count("sh"), 0u) << "a placeholder process";
  EXPECT_GT(lf.logger.rotate, 0);  // bounded logging on a boot service
  EXPECT_GT(lf.logger.split_mb, 0);
}

// Issue 14 items 6 and 7: every vehicle launch file runs tiller-failsafe; the real ones run their
// sensor drivers and tiller-nav and no placeholder; the simulated ones give tiller-sim its
// simulated sensors (the failsafe's power, leak and depth readings).
TEST(LaunchFiles, VehicleFilesRunTheFailsafeOnSensors) {
  const std::string root = TILLER_SOURCE_DIR;
  const auto commands = [&](const std::string& base) {
    std::map<std::string, std::vector<std::string>> out;  // command -> its arguments
    for (const auto& p : load_launch_file(root + "/config/launch/" + base).processes)
      out[p.command] = p.args;
    return out;
  };
  const std::vector<std::string> rov_drivers = {"tiller-pressure", "tiller-imu", "tiller-leak",
                                                "tiller-power",    "tiller-nav", "tiller-failsafe"};
  for (const char* f : {"real_seed000_rov.yaml", "real_seed001_rov.yaml"}) {
    SCOPED_TRACE(f);
    const auto c = commands(f);
    for (const auto& d : rov_drivers) EXPECT_EQ(c.count(d), 1u) << d;
    EXPECT_EQ(c.count("sh"), 0u);
    ASSERT_EQ(c.count("tiller-nav"), 1u);
    EXPECT_NE(c.at("tiller-nav")[1].find("config/nav/rov.yaml"), std::string::npos);
  }
  int sims = 0;
  for (const auto& e : fs::directory_iterator(root + "/config/launch")) {
    const std::string base = e.path().filename().string();
    if (base.rfind("sim_", 0) != 0 && base.rfind("vehicle_sim_", 0) != 0) continue;
    SCOPED_TRACE(base);
    const auto c = commands(base);
    ASSERT_EQ(c.count("tiller-sim"), 1u);
    ++sims;
    const auto& a = c.at("tiller-sim");
    const auto s = std::find(a.begin(), a.end(), "--sensors");
    ASSERT_NE(s, a.end()) << "tiller-sim without --sensors";
    ASSERT_NE(s + 1, a.end());
    const bool boat = std::find(a.begin(), a.end(), "config/vehicles/otter.yaml") != a.end();
    EXPECT_EQ(*(s + 1), boat ? "config/sim/sensors/usv.yaml" : "config/sim/sensors/rov.yaml");
    ASSERT_EQ(c.count("tiller-failsafe"), 1u);
    EXPECT_EQ(c.at("tiller-failsafe")[1],
              boat ? "config/failsafe/otter_sim.yaml" : "config/failsafe/rov_sim.yaml");
  }
  EXPECT_GE(sims, 9);
}

// Two devices at one address on one bus answer together and corrupt each other's transfers: in
// every real launch file each I2C (bus, address) is one process's (the INA226's default 0x40 is
// the PCA9685 board's too; config/sensors/power_ina226.yaml uses 0x41).
TEST(LaunchFiles, RealFilesGiveEveryI2cDeviceItsOwnAddress) {
  const std::string root = TILLER_SOURCE_DIR;
  for (const char* f : {"real_seed000_rov.yaml", "real_seed001_rov.yaml", "real_usv.yaml"}) {
    SCOPED_TRACE(f);
    std::map<std::pair<std::string, std::int64_t>, std::string> owner;
    int devices = 0;
    const auto take = [&](const std::string& bus, std::int64_t address, const std::string& who) {
      ++devices;
      const auto [it, fresh] = owner.emplace(std::make_pair(bus, address), who);
      EXPECT_TRUE(fresh) << who << " and " << it->second << " both at " << address << " on " << bus;
    };
    for (const auto& p : load_launch_file(root + "/config/launch/" + f).processes) {
      const auto c = std::find(p.args.begin(), p.args.end(), "--config");
      if (c == p.args.end() || c + 1 == p.args.end()) continue;
      const config::Value v = config::Value::load_file(root + "/" + substitute(*(c + 1), {}));
      if (p.command == "tiller-esc") {
        const std::string backend = v.string("backend");
        if (backend == "pca9685") {
          take(v.at("pca9685").string("bus"), v.at("pca9685").integer("address"), p.name);
        } else if (backend == "i2c_tgy") {
          for (const auto& e : v.at("escs").items())
            take(v.at("i2c_tgy").string("bus"), e.integer("address"), p.name);
        }
      } else if (p.command == "tiller-pressure" || p.command == "tiller-imu" ||
                 p.command == "tiller-power") {
        take(v.string("bus"), v.integer_or("address", 0x76), p.name);
      }
    }
    EXPECT_GE(devices, 3);
  }
}

}  // namespace
}  // namespace tiller::launch
