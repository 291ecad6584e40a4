// Records a golden log: the simulated Otter and the whole stack (sim, esc, mixer, velocity PID,
// station keeping, path follower, mission) in one process on lockstep time, every message
// written to an LCM log, plus the replay manifest naming each process's config.
// Used by tools/rerecord-golden; not a test.
//   tiller-golden-record MISSION SECONDS OUT.lcmlog
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "esc/esc_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/log.hpp"
#include "sim/sim_node.hpp"

using namespace tiller;

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: tiller-golden-record MISSION SECONDS OUT.lcmlog (run from the repository "
                 "root)\n";
    return 2;
  }
  try {
    const std::string sim_cfg = "test/data/golden/sim_otter.yaml",
                      esc_cfg = "config/esc/otter_sim.yaml", mixer_cfg = "config/mixer/otter.yaml",
                      control_cfg = "config/control/otter.yaml",
                      follower_cfg = "config/guidance/default.yaml";
    SimNode sim(sim_cfg);
    EscNode esc(esc_cfg);
    MixerNode mixer(mixer_cfg);
    control::VelocityPidNode vpid(
        control::load_velocity_pid_node_params(config::Value::load_file(control_cfg)));
    control::StationKeepNode skeep(
        control::load_station_keep_node_params(config::Value::load_file(control_cfg)));
    const auto froot = config::Value::load_file(follower_cfg);
    guidance::PathFollowerNode follower(guidance::load_follower_node_params(froot));
    const auto m = mission::load_mission_file(argv[1]);
    mission::MissionNode mission(m, 1, kUsPerSecond);
    LockstepExecutor ex(0);
    for (Node* n :
         std::initializer_list<Node*>{&sim, &esc, &mixer, &vpid, &skeep, &follower, &mission})
      ex.add(*n);
    std::filesystem::remove(argv[3]);
    LogWriter log(argv[3]);
    std::size_t events = 0;
    ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      log.write(ch, d, n, t);
      ++events;
    });
    ex.run_until(from_seconds(std::atof(argv[2])));
    std::cout << argv[3] << ": " << events << " events, " << std::atof(argv[2]) << " s\n";
    const std::filesystem::path out(argv[3]);
    std::ofstream manifest((out.parent_path() / out.stem()).string() + ".replay.yaml");
    manifest << "# Written by tools/rerecord-golden with " << out.filename().string()
             << ": the config of each process when it was recorded.\n"
             << "# A lockstep log: replay must match bit for bit, heartbeats included.\n"
             << "processes:\n  sim: " << sim_cfg << "\n  esc: " << esc_cfg
             << "\n  mixer: " << mixer_cfg << "\n  velocity-pid: " << control_cfg
             << "\n  station-keep: " << control_cfg << "\n  path-follower: " << follower_cfg
             << "\nheartbeats: true\ntolerance: 0\ntime_tolerance_ms: 0\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "tiller-golden-record: " << e.what() << "\n";
    return 2;
  }
}
