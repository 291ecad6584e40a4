// A log played with the real lcm-logplayer (a client Tiller did not write) into running Tiller
// processes, restamped to now first by tiller-log restamp (nodes refuse messages whose own utime
// is older than their freshness limit): the first 12 s of the golden log's inputs to the simulator
// (TILLER_ESC_OUTPUT) and the mixer (wrenches, arbitration, arm state, the operator's START) are
// played into a live tiller-sim and tiller-mixer started by tiller-launch, with lcm-logger
// recording. Their live answers must match the recorded ones within a tolerance: the simulated pose
// within 0.3 m and 5 deg of the recorded ground truth, and nearly every thruster command within
// 0.02 of a recorded command published within 30 ms of it. Runs in a private network namespace
// (NETNS).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "core/angles.hpp"
#include "logtools/log_io.hpp"
#include "runtime/channels.hpp"
#include "runtime/log.hpp"

namespace tiller {
namespace {

namespace fs = std::filesystem;

TEST(LogPlayer, LiveSimAndMixerRespondAsRecorded) {
  const std::string src = TILLER_SOURCE_DIR;
  const fs::path dir =
      fs::temp_directory_path() / ("tiller-logplayer-test-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto golden = logtools::read_any_log(src + "/test/data/golden/usv_short.lcmlog.gz");
  ASSERT_FALSE(golden.empty());
  const TimeUs t0 = golden.front().time;
  const TimeUs clip_end = t0 + 12 * kUsPerSecond;
  const std::string inputs =
      "^TILLER_(ESC_OUTPUT|WRENCH_VELOCITY|WRENCH_STATION|ARBITRATION|ARM_STATE|MANUAL_DEMAND|"
      "MISSION_COMMAND)$";
  const std::regex in_re(inputs);
  std::vector<Event> clip;
  {
    LogWriter w((dir / "clip.lcmlog").string());
    for (const auto& e : golden) {
      if (e.time < clip_end && std::regex_match(e.channel, in_re)) {
        w.write(e);
        clip.push_back(e);
      }
    }
  }
  ASSERT_GT(clip.size(), 1000u);
  std::ofstream(dir / "run.yaml")
      << "name: logplayer-test\nroot: " << src << "\ngrace_s: 2\nends_with: player\n"
      << "processes:\n"
      << "  - {name: sim, command: tiller-sim, args: [--config, test/data/golden/sim_otter.yaml]}\n"
      << "  - {name: mixer, command: tiller-mixer, args: [--config, config/mixer/otter.yaml]}\n"
      // The clip's utimes are the golden log's; every node refuses a message older than its
      // freshness limit by its utime, so the clip is restamped to start now, just before playing.
      << "  - {name: player, command: sh, args: [-c, \"" << TILLER_BIN_DIR << "/tiller-log restamp "
      << (dir / "clip.lcmlog").string() << " " << (dir / "fresh.lcmlog").string()
      << " && exec lcm-logplayer " << (dir / "fresh.lcmlog").string()
      << "\"], start_delay_s: 1.0}\n";
  const std::string live_path = (dir / "live.lcmlog").string();
  const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-launch " +
                          (dir / "run.yaml").string() + " --log-file " + live_path +
                          " --status-file " + (dir / "status").string() + " > " +
                          (dir / "out.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(dir / "out.txt").rdbuf();
  const auto live = read_log(live_path);

  // Map live times to log times with the first played message (its bytes as recorded but for
  // the restamped utime, bytes 8..15).
  auto same_but_utime = [](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    if (a.size() != b.size() || a.size() < 16) return false;
    return std::equal(a.begin(), a.begin() + 8, b.begin()) &&
           std::equal(a.begin() + 16, a.end(), b.begin() + 16);
  };
  TimeUs offset = 0;
  bool found = false;
  for (const auto& e : live) {
    if (e.channel == clip.front().channel && same_but_utime(e.data, clip.front().data)) {
      offset = e.time - clip.front().time;
      found = true;
      break;
    }
  }
  ASSERT_TRUE(found) << "the played messages were not logged";

  // Simulator: live pose against the recorded ground truth at the same log time.
  std::vector<std::pair<TimeUs, odometry_t>> live_truth;
  for (const auto& e : live) {
    odometry_t o;
    if (e.channel == channels::kGroundTruth && decode(e, o))
      live_truth.emplace_back(e.time - offset, o);
  }
  ASSERT_FALSE(live_truth.empty());
  int compared = 0;
  double worst_pos = 0, worst_yaw = 0;
  for (const auto& e : golden) {
    odometry_t rec;
    if (e.channel != channels::kGroundTruth || e.time < t0 + kUsPerSecond ||
        e.time > clip_end - 500'000 || !decode(e, rec))
      continue;
    auto it =
        std::min_element(live_truth.begin(), live_truth.end(), [&](const auto& a, const auto& b) {
          return std::llabs(a.first - e.time) < std::llabs(b.first - e.time);
        });
    if (std::llabs(it->first - e.time) > 30'000) continue;
    ++compared;
    worst_pos = std::max(worst_pos, std::hypot(it->second.position[0] - rec.position[0],
                                               it->second.position[1] - rec.position[1]));
    worst_yaw =
        std::max(worst_yaw, std::fabs(angle_diff(it->second.orientation[2], rec.orientation[2])));
  }
  EXPECT_GT(compared, 150);  // ~10.5 s at 20 Hz, less those without a live sample within 30 ms
  EXPECT_LT(worst_pos, 0.3) << "m";
  EXPECT_LT(worst_yaw, deg_to_rad(5.0)) << "rad";
  std::printf("sim: %d poses compared, worst position %.3f m, worst heading %.2f deg\n", compared,
              worst_pos, worst_yaw * 180 / M_PI);

  // Mixer: each live armed command matches a recorded command within 30 ms and 0.02.
  std::vector<std::pair<TimeUs, thruster_command_t>> rec_cmd;
  for (const auto& e : golden) {
    thruster_command_t c;
    if (e.channel == channels::kThrusterCommand && decode(e, c)) rec_cmd.emplace_back(e.time, c);
  }
  int live_armed = 0, matched = 0;
  for (const auto& e : live) {
    thruster_command_t c;
    if (e.channel != channels::kThrusterCommand || !decode(e, c) || !c.armed) continue;
    const TimeUs t = e.time - offset;
    if (t < t0 + 500'000 || t > clip_end - 500'000) continue;
    ++live_armed;
    for (const auto& [tr, r] : rec_cmd) {
      if (std::llabs(tr - t) > 30'000 || r.n_thrusters != c.n_thrusters) continue;
      double d = 0;
      for (int k = 0; k < c.n_thrusters; ++k)
        d = std::max(d, std::fabs(r.command[static_cast<std::size_t>(k)] -
                                  c.command[static_cast<std::size_t>(k)]));
      if (d <= 0.02) {
        ++matched;
        break;
      }
    }
  }
  std::printf("mixer: %d of %d live armed commands match a recorded one\n", matched, live_armed);
  EXPECT_GT(live_armed, 400);  // 11 s at 50 Hz or more
  EXPECT_GE(matched, live_armed * 95 / 100);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tiller
