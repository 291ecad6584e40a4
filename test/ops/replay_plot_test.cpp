// Replay regression machinery on a toy gain node (independent of the real stack): a replay of
// a lockstep log through the same node matches bit for bit; a changed gain is reported with
// the first differing field, its time and old/new values; tolerance and count differences; a
// live-like log replays with ticks where the recording ran them (a fixed grid does not match),
// extra replayed messages are counted, integrating processes are not in a live verdict.
// And tiller-plot draws a synthetic run into a 1600x1200 PNG with gnuplot.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <tiller/odometry_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "logtools/plotdata.hpp"
#include "replaytool/compare.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/log.hpp"

namespace tiller::replaytool {
namespace {

// Publishes tau[0] = -gain * north on every tick, from the latest odometry.
class GainNode : public Node {
 public:
  explicit GainNode(double gain) : Node("gain", 50'000), gain_(gain) {
    subscribe(channels::kOdometry, &GainNode::on_odom);
    advertise<wrench_t>(channels::kWrenchVelocity);  // a listed output is compared if advertised
  }
  void on_odom(const odometry_t& m, TimeUs) { north_ = m.position[0]; }
  void on_tick(TimeUs now) override {
    wrench_t w{};
    w.utime = now;
    w.source = wrench_t::SOURCE_VELOCITY_PID;
    w.tau[0] = -gain_ * north_;
    w.valid = true;
    publish(channels::kWrenchVelocity, w);
  }

 private:
  double gain_;
  double north_ = 0.0;
};

std::vector<Event> record(double gain) {
  GainNode n(gain);
  LockstepExecutor ex(0);
  ex.add(n);
  std::vector<Event> log;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int sz, TimeUs t) {
    log.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + sz)});
  });
  for (int k = 0; k < 40; ++k) {
    odometry_t o{};
    o.utime = 10'000 + k * 30'000;
    o.position[0] = 0.1 * k;
    ex.inject(channels::kOdometry, o, o.utime);
  }
  ex.run_until(1'300'000);
  return log;
}

ProcessEntry gain_entry() {
  return {"gain", "", {channels::kWrenchVelocity}, [](const std::string& c) {
            return std::make_unique<GainNode>(std::atof(c.c_str()));
          }};
}

TEST(Replay, SameCodeMatchesBitForBit) {
  const auto log = record(2.0);
  const auto rep = replay_process(gain_entry(), "2.0", log, {}, true);
  EXPECT_TRUE(rep.ok()) << format_report(rep);
  ASSERT_EQ(rep.channels.size(), 2u);  // heartbeat and wrench
  EXPECT_EQ(rep.channels[1].channel, channels::kWrenchVelocity);
  EXPECT_EQ(rep.channels[1].matching, 27u);  // ticks at 0, 50 ms, ..., 1.3 s
  EXPECT_EQ(rep.inputs, 40u);
}

TEST(Replay, ChangedGainIsCaughtWithTheFirstDifference) {
  const auto log = record(2.0);
  const auto rep = replay_process(gain_entry(), "2.5", log, {}, false);
  ASSERT_FALSE(rep.ok());
  ASSERT_EQ(rep.channels.size(), 1u);  // heartbeats not compared
  const auto& c = rep.channels[0];
  ASSERT_TRUE(c.first.has_value());
  // First non-zero north is 0.1 (delivered at 40 ms), seen by the tick at 50 ms.
  EXPECT_EQ(c.first->time, 50'000);
  EXPECT_EQ(c.first->field, "tau[0]");
  EXPECT_EQ(c.first->old_value, "-0.20000000000000001");
  EXPECT_EQ(c.first->new_value, "-0.25");
  EXPECT_EQ(c.differing, 26u);  // every tick but the first (north = 0)
  const std::string text = format_report(rep);
  EXPECT_NE(text.find("first difference: message 1 at t=0.050000 s, tau[0]: old "
                      "-0.20000000000000001, new -0.25"),
            std::string::npos)
      << text;
  // Within a tolerance larger than the biggest change (0.5 * 3.9 = 1.95 N) it passes.
  EXPECT_TRUE(replay_process(gain_entry(), "2.5", log, Tolerance{2.0, 0}, false).ok());
  EXPECT_FALSE(replay_process(gain_entry(), "2.5", log, Tolerance{1.9, 0}, false).ok());
}

TEST(Replay, CountAndTimeDifferences) {
  auto log = record(2.0);
  std::vector<Event> old_w, new_w;
  for (const auto& e : log)
    if (e.channel == channels::kWrenchVelocity) old_w.push_back(e);
  new_w = old_w;
  new_w.pop_back();
  auto r = compare_channel("W", old_w, new_w, {});
  EXPECT_FALSE(r.ok());
  ASSERT_TRUE(r.first);
  EXPECT_EQ(r.first->field, "count");
  EXPECT_EQ(r.first->old_value, "27");
  EXPECT_EQ(r.first->new_value, "26");
  new_w = old_w;
  new_w[3].time += 1000;
  r = compare_channel("W", old_w, new_w, {});
  EXPECT_EQ(r.first->field, "time");
  EXPECT_TRUE(compare_channel("W", old_w, new_w, Tolerance{0, 1000}).ok());
}

// A live-like log made from a lockstep one (tick T sees the inputs before T): lcm-logger sees
// each tick's outputs 400 us after its grid time; an input stamped exactly at a grid point
// (which the tick did not see) 500 us after it, after that tick's outputs; and the odometry of
// 40 ms (seen by the 50 ms tick) late, at 50.2 ms, yet before that tick's outputs at 50.4 ms (the
// live node had it in time). The live replay runs each tick where the recording shows it ran:
// the same code matches every message; a fixed-grid replay, or a changed gain, does not.
std::vector<Event> live_like(double gain) {
  auto log = record(gain);
  for (auto& e : log) {
    if (e.channel != channels::kOdometry)
      e.time += 400;
    else if (e.time == 40'000)
      e.time = 50'200;
    else if (e.time % 50'000 == 0)
      e.time += 500;
  }
  std::stable_sort(log.begin(), log.end(),
                   [](const Event& a, const Event& b) { return a.time < b.time; });
  return log;
}

TEST(Replay, LiveLogTicksWhereTheRecordingRanThem) {
  ReplayOptions o;
  o.live = true;
  const Tolerance tol{0, 20'000};
  auto rep = replay_process(gain_entry(), "2.0", live_like(2.0), tol, o);
  EXPECT_TRUE(rep.ok()) << format_report(rep);
  ASSERT_EQ(rep.channels.size(), 1u);  // heartbeats are not compared in a live replay
  EXPECT_EQ(rep.channels[0].matching, 27u) << format_report(rep);
  EXPECT_EQ(rep.channels[0].unmatched_replayed, 0u);
  EXPECT_EQ(rep.aligned_ticks, rep.ticks);
  EXPECT_EQ(rep.ticks, 27u);
  // The fixed-grid executor would run the 250 ms tick before the late odometry: a difference.
  ReplayOptions grid;
  EXPECT_FALSE(replay_process(gain_entry(), "2.0", live_like(2.0), tol, grid).ok());
  // A changed gain fails the live replay, even with live_match 0.5 (26 of 27 messages differ).
  Tolerance half = tol;
  half.live_match = 0.5;
  rep = replay_process(gain_entry(), "2.5", live_like(2.0), half, o);
  EXPECT_FALSE(rep.ok()) << format_report(rep);
  EXPECT_EQ(rep.channels[0].differing, 26u);
  // An integrating process is reported but not in the verdict.
  auto integ = gain_entry();
  integ.integrating = true;
  rep = replay_process(integ, "2.5", live_like(2.0), half, o);
  EXPECT_TRUE(rep.ok());
  EXPECT_NE(format_report(rep).find("not in the verdict"), std::string::npos);
}

// In-order time matching counts extra replayed messages; live_match tolerates a fraction.
TEST(Replay, ExtraReplayedMessagesAreCounted) {
  auto log = record(2.0);
  std::vector<Event> old_w, new_w;
  for (const auto& e : log)
    if (e.channel == channels::kWrenchVelocity) old_w.push_back(e);
  new_w = old_w;
  new_w.insert(new_w.begin() + 5, new_w[5]);  // one extra, at the same time
  new_w[6].time += 1;
  auto r = compare_channel("W", old_w, new_w, Tolerance{0, 1000});
  EXPECT_EQ(r.unmatched_replayed, 1u);
  EXPECT_EQ(r.matching, 27u);
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(compare_channel("W", old_w, new_w, Tolerance{0, 1000, 0, 0.9}).ok());
}

TEST(Plot, DrawsASyntheticRunToPng) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("tiller-plot-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string log_path = (dir / "run.lcmlog").string();
  {
    LogWriter w(log_path);
    path_t p{};
    p.n_waypoints = 3;
    p.waypoints.resize(3);
    p.waypoints[1].position[0] = 20;
    p.waypoints[2].position[0] = 20;
    p.waypoints[2].position[1] = 20;
    const auto pe = encode(channels::kPath, 0, p);
    w.write(pe);
    for (int k = 0; k < 200; ++k) {
      const TimeUs t = k * 100'000;
      odometry_t o{};
      o.position[0] = std::min(20.0, 0.2 * k);
      o.position[1] = k > 100 ? 0.2 * (k - 100) : 0.0;
      o.orientation[2] = k > 100 ? M_PI / 2 : 0.0;
      o.velocity[0] = 2.0;
      w.write(encode(channels::kGroundTruth, t, o));
      velocity_setpoint_t s{};
      s.active = true;
      s.velocity[0] = 2.0;
      s.velocity[1] = 0.5;
      w.write(encode(channels::kVelocitySetpoint, t, s));
      thruster_command_t c{};
      c.n_thrusters = 2;
      c.names = {"port", "starboard"};
      c.command = {std::sin(0.05 * k), 1.0};
      w.write(encode(channels::kThrusterCommand, t, c));
    }
  }
  // The extracted numbers: speed = |(u, v)|, setpoint speed = |(2, 0.5)|, last path kept.
  const auto pd = logtools::write_plot_data(read_log(log_path), dir.string());
  EXPECT_EQ(pd.trajectory_source, channels::kGroundTruth);
  EXPECT_EQ(pd.trajectory_rows, 200u);
  EXPECT_EQ(pd.path_points, 3u);
  EXPECT_EQ(pd.thruster_names, (std::vector<std::string>{"port", "starboard"}));
  std::ifstream sp(dir / "setpoint.csv");
  std::string header, row;
  std::getline(sp, header);
  std::getline(sp, row);
  EXPECT_EQ(row, "0,2.06155,NaN,1,0");
  const std::string png = (dir / "run.png").string();
  const std::string cmd = std::string(TILLER_BIN_DIR) + "/tiller-plot " + log_path + " --output " +
                          png + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(png, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  EXPECT_EQ(h[1], 'P');
  EXPECT_EQ(h[2], 'N');
  EXPECT_EQ(h[3], 'G');
  const unsigned width = (h[16] << 24) | (h[17] << 16) | (h[18] << 8) | h[19];
  const unsigned height = (h[20] << 24) | (h[21] << 16) | (h[22] << 8) | h[23];
  EXPECT_EQ(width, 1600u);
  EXPECT_EQ(height, 1200u);
  EXPECT_GT(fs::file_size(png), 20'000u);  // a drawn figure, not an empty canvas
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tiller::replaytool
