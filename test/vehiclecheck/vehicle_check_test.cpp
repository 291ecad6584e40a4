// tiller-check-vehicle's logic on planted trees: a vehicle with all its files passes; a missing
// mixer or ESC config, an ESC config that leaves a thruster out, a broken controller file and a
// launch file naming a missing teleop preset each fail, naming the file. The shipped vehicles are
// checked by the vehicle_check_test entry (tools/check-vehicle on config/vehicles/*.yaml).
#include "vehiclecheck/vehicle_check.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace tiller::vehiclecheck {
namespace {

namespace fs = std::filesystem;
const fs::path kRoot = TILLER_SOURCE_DIR;

class Tree : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("vehicle-check-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    for (const char* d : {"vehicles", "mixer", "esc", "control", "guidance", "launch", "teleop"})
      fs::create_directories(dir_ / "config" / d);
    // The Otter's files, copied under another name: a complete boat.
    copy("vehicles/otter.yaml", "vehicles/boat.yaml");
    copy("vehicles/otter.yaml", "vehicles/otter.yaml");  // control/otter.yaml's munk_compensation
    write("mixer/boat.yaml", "vehicle: ../vehicles/boat.yaml\nrate_hz: 50\n");
    write("esc/boat_sim.yaml",
          "vehicle: ../vehicles/boat.yaml\nbackend: sim\nescs:\n  - {name: port, channel: 0}\n"
          "  - {name: starboard, channel: 1}\n");
    copy("control/otter.yaml", "control/boat.yaml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void copy(const std::string& from, const std::string& to) {
    fs::copy_file(kRoot / "config" / from, dir_ / "config" / to);
  }
  void write(const std::string& rel, const std::string& text) {
    std::ofstream(dir_ / "config" / rel) << text;
  }
  Report check() {
    return check_vehicle((dir_ / "config/vehicles/boat.yaml").string(), (dir_ / "config").string());
  }
  static bool has(const Report& r, Level level, const std::string& file, const std::string& what) {
    for (const auto& f : r.findings) {
      if (f.level == level && f.file.find(file) != std::string::npos &&
          f.what.find(what) != std::string::npos)
        return true;
    }
    return false;
  }

  fs::path dir_;
};

TEST_F(Tree, CompleteVehiclePasses) {
  const auto r = check();
  EXPECT_TRUE(r.ok()) << format(r);
  EXPECT_TRUE(has(r, Level::kOk, "config/mixer/boat.yaml", "tiller-mixer")) << format(r);
  EXPECT_TRUE(has(r, Level::kOk, "config/esc/boat_sim.yaml", "2 ESCs")) << format(r);
  EXPECT_TRUE(has(r, Level::kOk, "config/control/boat.yaml", "tiller-velocity-pid")) << format(r);
  EXPECT_TRUE(has(r, Level::kNote, "config/guidance/boat.yaml", "absent")) << format(r);
}

TEST_F(Tree, MissingMixerConfigFails) {
  fs::remove(dir_ / "config/mixer/boat.yaml");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/mixer/boat.yaml", "no mixer config names boat.yaml"))
      << format(r);
}

TEST_F(Tree, MissingEscConfigFails) {
  fs::remove(dir_ / "config/esc/boat_sim.yaml");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/esc/boat_sim.yaml", "no ESC config names")) << format(r);
}

TEST_F(Tree, EscConfigLeavingAThrusterOutFails) {
  write("esc/boat_sim.yaml",
        "vehicle: ../vehicles/boat.yaml\nbackend: sim\nescs:\n  - {name: port, channel: 0}\n");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/esc/boat_sim.yaml", "starboard")) << format(r);
}

TEST_F(Tree, MixerNamingAnotherFileOfTheSameNameFails) {
  fs::create_directories(dir_ / "config/other");
  copy("vehicles/wamv.yaml", "other/boat.yaml");
  write("mixer/boat.yaml", "vehicle: ../other/boat.yaml\n");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/mixer/boat.yaml", "not ")) << format(r);
}

TEST_F(Tree, BrokenControllerFileFails) {
  write("control/boat.yaml", "velocity_pid: {surge: {k_drgg: 1}}\n");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/control/boat.yaml", "")) << format(r);
}

TEST_F(Tree, VehicleWithoutDynamicsFails) {
  write("vehicles/boat.yaml",
        "name: boat\nthrusters:\n  - {name: port, position: [0, 0, 0], direction: [1, 0, 0], "
        "max_forward_n: 10, max_reverse_n: 10, curve: {linear: {forward_n: 10, reverse_n: 10}}, "
        "group: g, reversed: false}\nallocation: {strategy: clip}\n");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kFail, "config/vehicles/boat.yaml", "dynamics")) << format(r);
}

TEST_F(Tree, LaunchFileWithAMissingTeleopPresetFails) {
  write(
      "launch/sim_boat.yaml",
      "name: sim-boat\nroot: ../..\nprocesses:\n  - name: mixer\n    command: tiller-mixer\n"
      "    args: [--config, config/mixer/boat.yaml]\n  - name: teleop\n    command: tiller-teleop\n"
      "    args: [--config, config/teleop/nope.yaml]\n");
  const auto r = check();
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Level::kOk, "config/launch/sim_boat.yaml", "2 processes")) << format(r);
  EXPECT_TRUE(has(r, Level::kFail, "config/teleop/nope.yaml", "")) << format(r);
}

}  // namespace
}  // namespace tiller::vehiclecheck
