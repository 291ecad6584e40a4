// MixerNode in the lockstep executor: neutral while disarmed or without a valid source; output
// at once on new input and at the configured rate; stale inputs become absent; NaN or
// out-of-range input gives neutral and a counter; the arbitration picks the source and its
// absence falls back to the config's source; config paths resolve from any directory.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include <tiller/controller_mode_t.hpp>

#include "mixer/mixer_node.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/replay.hpp"

namespace tiller {
namespace {

const std::string kSrc = TILLER_SOURCE_DIR;

struct Seen {
  TimeUs t;
  thruster_command_t cmd;
};

class MixerTest : public ::testing::Test {
 protected:
  void SetUp() override { start("seed000_rov4"); }
  void start(const std::string& vehicle) {
    start_file(kSrc + "/config/mixer/" + vehicle + ".yaml");
  }
  void start_file(const std::string& path) {
    seen.clear();
    gate_met = false;
    statuses = 0;
    node = std::make_unique<MixerNode>(path);
    ex = std::make_unique<LockstepExecutor>(0);
    ex->add(*node);
    ex->observe([this](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      if (ch == channels::kThrusterCommand) {
        Seen s{t, {}};
        ASSERT_EQ(s.cmd.decode(d, 0, n), n);
        seen.push_back(s);
      } else if (ch == channels::kAllocationStatus) {
        ASSERT_EQ(status.decode(d, 0, n), n);
        ++statuses;
      }
    });
  }
  // Arms, and meets the safety gate's start condition (lib/safety/intent_gate.hpp, tested on its
  // own in test/safety): a centred stick for the pilot, an operator START for the autonomy.
  void arm(TimeUs at, bool armed = true) {
    arm_state_t a{};
    a.utime = at;
    a.armed = armed;
    a.session = 1;
    ex->inject(channels::kArmState, a, at);
    if (!armed || gate_met) return;
    gate_met = true;
    manual(at, 0, 0);
    go(at);
  }
  void go(TimeUs at) {
    mission_command_t g{};
    g.utime = at;
    g.command_id = ++go_id;
    g.command = mission_command_t::START;
    ex->inject(channels::kMissionCommand, g, at);
  }
  bool gate_met = false;
  std::int64_t go_id = 0;
  void manual(TimeUs at, double x, double y, double n = 0, bool valid = true,
              const std::string& station = "") {
    manual_demand_t m{};
    m.utime = at;
    m.station = station;
    m.demand[0] = x;
    m.demand[1] = y;
    m.demand[5] = n;
    m.valid = valid;
    ex->inject(channels::kManualDemand, m, at);
  }
  void wrench(const char* ch, TimeUs at, double x, double nn = 0, std::int8_t src = 2) {
    wrench_t w{};
    w.utime = at;
    w.source = src;
    w.tau[0] = x;
    w.tau[5] = nn;
    w.valid = true;
    ex->inject(ch, w, at);
  }
  void arbitration(TimeUs at, std::int8_t source) {
    arbitration_t a{};
    a.utime = at;
    a.active_source = source;
    a.mode = source == wrench_t::SOURCE_VELOCITY_PID || source == wrench_t::SOURCE_STATION_KEEP
                 ? controller_mode_t::WAYPOINTING
                 : controller_mode_t::MANUAL_OPEN_LOOP;
    a.reason = "test";
    ex->inject(channels::kArbitration, a, at);
    if (a.mode == controller_mode_t::WAYPOINTING) go(at);
  }
  bool neutral(const thruster_command_t& c) {
    for (double v : c.command)
      if (v != 0.0) return false;
    return true;
  }
  std::unique_ptr<MixerNode> node;
  std::unique_ptr<LockstepExecutor> ex;
  std::vector<Seen> seen;
  allocation_status_t status{};
  int statuses = 0;
};

TEST_F(MixerTest, NeutralWhileDisarmedThenFollowsTheStickAtOnce) {
  manual(5'000, 1.0, 0.5);
  ex->run_until(100'000);
  ASSERT_FALSE(seen.empty());
  for (const auto& s : seen) {
    EXPECT_FALSE(s.cmd.armed);
    EXPECT_TRUE(neutral(s.cmd));
  }
  EXPECT_GT(node->counter_value("neutral.disarmed"), 0);
  arm(105'000);
  manual(107'000, 1.0, 0.5);  // between ticks (20 ms grid): answered at 107 ms, not 120 ms
  ex->run_until(107'000);
  ASSERT_EQ(seen.back().t, 107'000);
  const auto& c = seen.back().cmd;
  EXPECT_TRUE(c.armed);
  EXPECT_EQ(c.source, wrench_t::SOURCE_MANUAL_DEMAND);
  ASSERT_EQ(c.n_thrusters, 4);
  EXPECT_EQ(c.names[0], "t1");
  // Seed 000: stick (jx = 0.5 right, jy = 1 forward) is nearer the 2,4 axis: a = 1 on t2 and
  // t4, b = tan(45 deg - 63.4 deg) in size = 1/3 on t1 and t3 (seeds_test has the whole grid).
  AllocationResult r;
  Wrench j = Wrench::Zero();
  j(0) = 1.0;
  j(1) = 0.5;
  node->allocator().allocate_manual(j, r);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(c.command[static_cast<std::size_t>(i)], r.command[static_cast<std::size_t>(i)]);
  EXPECT_NEAR(c.command[1], 1.0, 1e-12);
  EXPECT_NEAR(c.command[3], -1.0, 1e-12);
  EXPECT_NEAR(std::abs(c.command[0]), 1.0 / 3, 1e-12);
  // The status goes out with every command.
  EXPECT_EQ(status.n_thrusters, 4);
  EXPECT_EQ(status.strategy, "direction_preserving");
  EXPECT_TRUE(status.axis_unactuated[2]);
  EXPECT_EQ(status.demanded[0], 1.0);
}

// Issue 30, scenario 3 in the mixer: armed for station A, the stick of station B (same key) is
// refused and counted, never followed, and never a flip between the two; after a takeover by
// B (a new session, controller B) it is A's stick that is refused, and B starts from neutral.
TEST_F(MixerTest, OnlyTheStationInControlIsFollowed) {
  arm_state_t a{};
  a.utime = 100'000;
  a.armed = true;
  a.session = 1;
  a.controller = "A";
  ex->inject(channels::kArmState, a, 100'000);
  manual(100'000, 0, 0, 0, true, "A");  // A's centred stick: the start condition
  int flips = 0, b_followed = 0;
  double last_sign = 0;
  for (TimeUs t = 120'000; t < 1'120'000; t += 10'000) {
    manual(t, 0.6, 0, 0, true, "A");           // A forward
    manual(t + 5'000, -0.9, 0, 0, true, "B");  // B full astern, in between
  }
  ex->run_until(1'120'000);
  for (const auto& sn : seen) {
    if (sn.t <= 120'000 || neutral(sn.cmd)) continue;
    const double sgn = sn.cmd.command[1] > 0 ? 1 : -1;
    if (last_sign != 0 && sgn != last_sign) ++flips;
    last_sign = sgn;
    if (std::abs(sn.cmd.command[1] + 0.9) < 1e-9 || sgn < 0) ++b_followed;
  }
  EXPECT_EQ(flips, 0);
  EXPECT_EQ(b_followed, 0);
  EXPECT_GT(last_sign, 0) << "A's stick was followed";
  EXPECT_GE(node->counter_value("rejected.manual_demand.station"), 95);
  // B takes over: a new session naming B. A's stick is refused now; B must centre first.
  a.utime = 1'130'000;
  a.session = 2;
  a.controller = "B";
  ex->inject(channels::kArmState, a, 1'130'000);
  const std::size_t from = seen.size();
  for (TimeUs t = 1'140'000; t < 1'400'000; t += 10'000) {
    manual(t, 0.6, 0, 0, true, "A");
    manual(t + 5'000, -0.9, 0, 0, true, "B");  // held astern: not centred, so neutral
  }
  ex->run_until(1'400'000);
  ASSERT_GT(seen.size(), from);
  for (std::size_t i = from; i < seen.size(); ++i) EXPECT_TRUE(neutral(seen[i].cmd)) << i;
  manual(1'405'000, 0, 0, 0, true, "B");
  manual(1'410'000, -0.9, 0, 0, true, "B");
  ex->run_until(1'410'000);
  EXPECT_FALSE(neutral(seen.back().cmd)) << "B, centred first, is followed";
}

TEST_F(MixerTest, PublishesAtTheConfiguredRate) {
  ex->run_until(1'000'000 - 1);
  EXPECT_EQ(seen.size(), 50u);  // 50 Hz, ticks at 0, 20, ..., 980 ms
  EXPECT_EQ(statuses, 50);
}

TEST_F(MixerTest, StaleInputsBecomeNeutral) {
  // Arm state refreshed until 2 s (as tiller-esc does at 10 Hz); the stick stops at 0 s.
  for (TimeUs t = 0; t <= 2'000'000; t += 100'000) arm(t);
  manual(0, 0.5, 0);
  ex->run_until(480'000);
  EXPECT_FALSE(neutral(seen.back().cmd));
  ex->run_until(520'000);  // manual freshness 0.5 s
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_FALSE(seen.back().cmd.armed);
  EXPECT_GE(node->stale(), 1);
  EXPECT_GT(node->counter_value("neutral.no_valid_input"), 0);
  // A stale arm state also means neutral: stick fresh again, esc silent.
  // (the stick came back after being stale: the gate wants it centred first)
  manual(2'080'000, 0, 0);
  for (TimeUs t = 2'100'000; t <= 3'000'000; t += 20'000) manual(t, 0.5, 0);
  ex->run_until(2'450'000);
  EXPECT_FALSE(neutral(seen.back().cmd));
  ex->run_until(2'600'000);  // last arm state at 2.0 s, limit 0.5 s
  EXPECT_TRUE(neutral(seen.back().cmd));
}

// Issue 12, finding 5, in the node: a mixer stopped (SIGSTOP) from 0.2 s to 4.2 s receives its
// queued input at 4.2 s (the live executor tells a message its receive time): an arm state, a
// centred stick, a push forward, another arm state, all stamped 0.25-0.4 s by their senders.
// Taken at their receive time they would meet the gate's centring condition and move the
// thrusters; by their utimes they are 3.8 s old and each is refused, counted and changes
// nothing. Then the first tick finds every input stale: neutral.
TEST_F(MixerTest, QueuedInputOfAStoppedMixerIsRefusedByItsUtime) {
  arm(100'000);
  manual(110'000, 1.0, 0);
  ex->run_until(200'000);
  ASSERT_TRUE(seen.back().cmd.armed);
  ASSERT_FALSE(neutral(seen.back().cmd));
  const TimeUs resumed = 4'200'000;
  auto acted_on = [&] {  // a command built now that is armed and off neutral
    const thruster_command_t& c = node->last_command();
    return c.utime == resumed && c.armed && !neutral(c);
  };
  arm_state_t a{};
  a.armed = true;
  a.session = 1;
  manual_demand_t m{};
  m.valid = true;
  a.utime = 250'000;
  node->on_arm_state(a, resumed);
  EXPECT_FALSE(acted_on());
  m.utime = 300'000;  // centred
  node->on_manual(m, resumed);
  EXPECT_FALSE(acted_on());
  m.utime = 350'000;
  m.demand[0] = 1.0;  // pushed forward again
  node->on_manual(m, resumed);
  EXPECT_FALSE(acted_on());
  a.utime = 400'000;
  node->on_arm_state(a, resumed);
  EXPECT_FALSE(acted_on());
  EXPECT_EQ(node->counter_value("rejected.arm_state.stale"), 2);
  EXPECT_EQ(node->counter_value("rejected.manual_demand.stale"), 2);
  node->tick(resumed);
  EXPECT_EQ(node->last_command().utime, resumed);
  EXPECT_FALSE(node->last_command().armed);
  EXPECT_TRUE(neutral(node->last_command()));
  // A fresh arm state and a fresh push (stamped now): armed, but the gate wants a fresh centring.
  a.utime = resumed;
  node->on_arm_state(a, resumed);
  m.utime = resumed;
  node->on_manual(m, resumed);
  EXPECT_TRUE(neutral(node->last_command()));
  EXPECT_EQ(node->gate_state(), safety::GateState::kWaitNeutral);
}

TEST_F(MixerTest, AMessageFromTheFutureIsRefused) {
  arm(100'000);
  ex->run_until(200'000);
  manual_demand_t m{};
  m.valid = true;
  m.demand[0] = 1.0;
  m.utime = 200'000 + kDefaultClockOffsetUs + 1;  // a sender's clock 0.25 s + 1 us ahead
  node->on_manual(m, 200'000);
  EXPECT_EQ(node->counter_value("rejected.manual_demand.future"), 1);
  EXPECT_TRUE(neutral(node->last_command()));
  mission_command_t g{};
  g.command = mission_command_t::START;
  g.command_id = 99;
  g.utime = 200'000 - kEventMaxAgeUs - kDefaultClockOffsetUs - 1;  // an operator's go, too late
  node->on_mission_command(g, 200'000);
  EXPECT_EQ(node->counter_value("rejected.mission_command.stale"), 1);
}

TEST_F(MixerTest, InvalidStickIsAbsentAndOutOfRangeIsCounted) {
  arm(0);
  manual(0, 0.5, 0);
  ex->run_until(10'000);
  EXPECT_FALSE(neutral(seen.back().cmd));
  manual(20'000, 0.5, 0, 0, /*valid=*/false);
  ex->run_until(20'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  manual(30'000, 0.5, 0);
  manual(40'000, 1.5, 0);  // out of [-1, 1]
  ex->run_until(40'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_EQ(node->counter_value("rejected.manual_demand.range"), 1);
  manual(50'000, std::nan(""), 0);
  ex->run_until(60'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_EQ(node->counter_value("rejected.manual_demand.range"), 2);
  EXPECT_EQ(node->rejected(), 2);
}

TEST_F(MixerTest, ArbitrationChoosesTheWrenchAndNanGivesNeutral) {
  arm(0);
  for (TimeUs t = 0; t <= 3'000'000; t += 100'000) arm(t);
  manual(0, 0.5, 0);
  arbitration(0, wrench_t::SOURCE_VELOCITY_PID);
  wrench(channels::kWrenchVelocity, 0, 20.0);
  wrench(channels::kWrenchStation, 0, -10.0);
  ex->run_until(10'000);
  EXPECT_EQ(seen.back().cmd.source, wrench_t::SOURCE_VELOCITY_PID);
  EXPECT_NEAR(node->last_result().achieved(0), 20.0, 1e-9);
  arbitration(20'000, wrench_t::SOURCE_STATION_KEEP);
  ex->run_until(20'000);
  EXPECT_EQ(seen.back().cmd.source, wrench_t::SOURCE_STATION_KEEP);
  EXPECT_NEAR(node->last_result().achieved(0), -10.0, 1e-9);
  // NaN on the active source: neutral at once, counted.
  wrench_t bad{};
  bad.valid = true;
  bad.tau[5] = std::nan("");
  ex->inject(channels::kWrenchStation, bad, 30'000);
  ex->run_until(30'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_EQ(node->counter_value("rejected.wrench.range"), 1);
  wrench(channels::kWrenchStation, 40'000, 2e5);  // beyond +-1e5
  ex->run_until(40'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_EQ(node->counter_value("rejected.wrench.range"), 2);
  // SOURCE_NONE: neutral even though a wrench is fresh.
  wrench(channels::kWrenchVelocity, 50'000, 20.0);
  arbitration(50'000, wrench_t::SOURCE_NONE);
  ex->run_until(50'000);
  EXPECT_TRUE(neutral(seen.back().cmd));
  // Arbitration goes stale (1 s): fallback_source manual_demand.
  // The pilot takes over again: centred first (the safety gate), then the stick.
  for (TimeUs t = 100'000; t <= 3'000'000; t += 50'000) manual(t, 0.3, 0);
  manual(1'060'000, 0, 0);
  ex->run_until(1'100'000);
  EXPECT_EQ(seen.back().cmd.source, wrench_t::SOURCE_MANUAL_DEMAND);
  EXPECT_FALSE(neutral(seen.back().cmd));
}

TEST_F(MixerTest, WrenchFeedsThatStopGiveNeutralAfterTheFreshnessLimit) {
  // For each controller source: the wrench stops at 200 ms; with the 0.5 s limit the commands
  // are the wrench's until 700 ms and neutral after it, and the neutral counter runs.
  for (std::int8_t src : {wrench_t::SOURCE_VELOCITY_PID, wrench_t::SOURCE_STATION_KEEP}) {
    SCOPED_TRACE(static_cast<int>(src));
    start("seed000_rov4");
    const char* ch =
        src == wrench_t::SOURCE_VELOCITY_PID ? channels::kWrenchVelocity : channels::kWrenchStation;
    for (TimeUs t = 0; t <= 2'000'000; t += 100'000) {
      arm(t);
      arbitration(t, src);
    }
    for (TimeUs t = 0; t <= 200'000; t += 20'000) wrench(ch, t, 30.0, 2.0);
    ex->run_until(690'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
    EXPECT_EQ(seen.back().cmd.source, src);
    EXPECT_NEAR(node->last_result().achieved(0), 30.0, 1e-9);
    const std::int64_t before = node->counter_value("neutral.no_valid_input");
    const std::int64_t stale_before = node->stale();
    ex->run_until(710'000);  // the tick at 700 ms is the last fresh one (limit inclusive)
    ex->run_until(760'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
    EXPECT_FALSE(seen.back().cmd.armed);
    EXPECT_EQ(seen.back().cmd.source, wrench_t::SOURCE_NONE);
    EXPECT_GT(node->counter_value("neutral.no_valid_input"), before);
    EXPECT_EQ(node->stale(), stale_before + 1);
    // Stays neutral while the feed is silent, and comes back with it.
    ex->run_until(1'500'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
    wrench(ch, 1'510'000, 30.0, 2.0);
    ex->run_until(1'510'000);
    EXPECT_EQ(seen.back().t, 1'510'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
  }
}

TEST_F(MixerTest, EveryMixerConfigIsNeutralOnStaleAndNanInput) {
  int configs = 0;
  for (const auto& e : std::filesystem::directory_iterator(kSrc + "/config/mixer")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    ++configs;
    start_file(e.path().string());
    const TimeUs limit = node->params().manual_timeout_us;
    for (TimeUs t = 0; t <= 4'000'000; t += 100'000) arm(t);
    // Stale stick: last at 0, neutral once older than its limit.
    manual(0, 0.5, 0.3, 0.2);
    ex->run_until(limit - 20'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
    ex->run_until(limit + 40'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
    EXPECT_GT(node->counter_value("neutral.no_valid_input"), 0);
    EXPECT_GE(node->stale(), 1);
    // NaN stick: neutral at once, counted (the stick back: centred first, the safety gate).
    manual(990'000, 0, 0);
    manual(1'000'000, 0.5, 0.3);
    ex->run_until(1'000'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
    manual(1'010'000, std::nan(""), 0.3);
    ex->run_until(1'010'000);
    EXPECT_EQ(seen.back().t, 1'010'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
    EXPECT_EQ(node->counter_value("rejected.manual_demand.range"), 1);
    // NaN and stale wrench on the active controller source.
    arbitration(2'000'000, wrench_t::SOURCE_VELOCITY_PID);
    wrench(channels::kWrenchVelocity, 2'000'000, 20.0, 1.0);
    ex->run_until(2'000'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
    wrench(channels::kWrenchVelocity, 2'010'000, std::nan(""));
    ex->run_until(2'010'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
    EXPECT_EQ(node->counter_value("rejected.wrench.range"), 1);
    wrench(channels::kWrenchVelocity, 2'020'000, 20.0, 1.0);
    arbitration(2'100'000, wrench_t::SOURCE_VELOCITY_PID);
    ex->run_until(2'100'000);
    EXPECT_FALSE(neutral(seen.back().cmd));
    ex->run_until(2'020'000 + node->params().wrench_timeout_us + 40'000);
    EXPECT_TRUE(neutral(seen.back().cmd));
  }
  EXPECT_GE(configs, 8);
}

TEST_F(MixerTest, PublishesAtOnceOnlyForTheActiveSourceAndForChanges) {
  for (TimeUs t = 0; t <= 1'000'000; t += 100'000) arm(t);
  arbitration(0, wrench_t::SOURCE_VELOCITY_PID);
  wrench(channels::kWrenchVelocity, 0, 20.0);
  ex->run_until(100'000);
  auto at = [&](TimeUs t) {
    int k = 0;
    for (const auto& s : seen) k += s.t == t ? 1 : 0;
    return k;
  };
  wrench(channels::kWrenchStation, 107'000, -10.0);     // not active: waits for the tick
  manual(109'000, 0.5, 0.0);                            // not active either
  wrench(channels::kWrenchVelocity, 113'000, 25.0);     // active: at once
  arbitration(115'000, wrench_t::SOURCE_VELOCITY_PID);  // no change
  arm(117'000);                                         // still armed: no change
  arbitration(123'000, wrench_t::SOURCE_STATION_KEEP);  // change: at once
  arm(127'000, false);                                  // disarm: at once
  ex->run_until(130'000);
  EXPECT_EQ(at(107'000), 0);
  EXPECT_EQ(at(109'000), 0);
  EXPECT_EQ(at(113'000), 1);
  EXPECT_EQ(at(115'000), 0);
  EXPECT_EQ(at(117'000), 0);
  EXPECT_EQ(at(120'000), 1);  // the tick
  ASSERT_EQ(at(123'000), 1);
  EXPECT_EQ(at(127'000), 1);
  EXPECT_TRUE(neutral(seen.back().cmd));
  for (const auto& s : seen) {
    if (s.t == 123'000) {
      EXPECT_EQ(s.cmd.source, wrench_t::SOURCE_STATION_KEEP);
    }
  }
  // Two feeds at 100 Hz and a stick at 100 Hz: the command rate is the tick plus the active
  // source's 100 Hz, not the sum of all feeds.
  arm(200'000);
  arbitration(200'000, wrench_t::SOURCE_VELOCITY_PID);
  for (TimeUs t = 200'005; t < 1'200'000; t += 10'000) {
    wrench(channels::kWrenchVelocity, t, 20.0);
    wrench(channels::kWrenchStation, t + 1'000, -20.0);
    manual(t + 2'000, 0.3, 0.0);
    if ((t - 200'005) % 100'000 == 0) {
      arm(t + 3'000);
      arbitration(t + 3'000, wrench_t::SOURCE_VELOCITY_PID);
    }
  }
  ex->run_until(1'199'999);
  // 200 ms to 1.2 s: 50 ticks + 100 velocity wrenches + re-arming and the switch back to
  // velocity_pid at 200 ms, and the operator START that opens the safety gate after re-arming;
  // nothing for the 100 station wrenches, 100 sticks, 10 + 10 repeats.
  std::size_t in_window = 0;
  for (const auto& s : seen) in_window += s.t >= 200'000 && s.t < 1'200'000 ? 1 : 0;
  EXPECT_EQ(in_window, 50u + 100u + 3u);
}

TEST_F(MixerTest, PublishAtOnceEveryInputIsTheOldBehaviourOnRequest) {
  // `publish_at_once: every_input` on a copy of config/mixer/otter.yaml.
  std::ifstream in(kSrc + "/config/mixer/otter.yaml");
  std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string rel = "vehicle: ../vehicles/otter.yaml";
  ASSERT_NE(yaml.find(rel), std::string::npos);
  yaml.replace(yaml.find(rel), rel.size(), "vehicle: " + kSrc + "/config/vehicles/otter.yaml");
  yaml += "publish_at_once: every_input\n";
  const std::string path = ::testing::TempDir() + "/mixer_every_input.yaml";
  std::ofstream(path) << yaml;
  start_file(path);
  EXPECT_TRUE(node->params().publish_every_input);
  arm(0);
  arbitration(0, wrench_t::SOURCE_VELOCITY_PID);
  ex->run_until(100'000);
  wrench(channels::kWrenchStation, 107'000, -10.0);
  manual(109'000, 0.5, 0.0);
  arm(111'000);
  ex->run_until(112'000);
  int k = 0;
  for (const auto& s : seen) k += s.t == 107'000 || s.t == 109'000 || s.t == 111'000 ? 1 : 0;
  EXPECT_EQ(k, 3);
  start("otter");  // the shipped configs publish at once for the active source only
  EXPECT_FALSE(node->params().publish_every_input);
}

TEST(MixerReplay, ReplayingTheInputsGivesTheSameBytes) {
  // A lockstep run with every kind of input, recorded; then the inputs alone replayed through a
  // fresh node: every output (commands, status, heartbeats) identical, bit for bit.
  const std::string cfg = kSrc + "/config/mixer/seed001_rov6.yaml";
  MixerNode a(cfg);
  LockstepExecutor ex(0);
  ex.add(a);
  std::vector<Event> inputs, outputs;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    Event e{ch, t, std::vector<std::uint8_t>(d, d + n)};
    (a.subscribes_to(ch) ? inputs : outputs).push_back(std::move(e));
  });
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (TimeUs t = 0; t < 3'000'000; t += 7'000) {
    if (t % 100'000 < 7'000) {
      arm_state_t arm{};
      arm.armed = t > 200'000;
      ex.inject(channels::kArmState, arm, t);
    }
    manual_demand_t m{};
    for (double& v : m.demand) v = u(rng);
    m.valid = true;
    ex.inject(channels::kManualDemand, m, t);
    wrench_t w{};
    w.valid = true;
    for (double& v : w.tau) v = 80 * u(rng);
    ex.inject(channels::kWrenchVelocity, w, t + 3'000);
    if (t % 700'000 == 0) {
      arbitration_t arb{};
      arb.active_source =
          t % 1'400'000 == 0 ? wrench_t::SOURCE_VELOCITY_PID : wrench_t::SOURCE_MANUAL_DEMAND;
      ex.inject(channels::kArbitration, arb, t + 1'000);
    }
  }
  ex.run_until(3'000'000);
  ASSERT_GT(outputs.size(), 500u);
  MixerNode b(cfg);
  ReplayExecutor rx(b);
  rx.run(inputs, TimeUs{0}, TimeUs{3'000'000});
  ASSERT_EQ(rx.outputs().size(), outputs.size());
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    ASSERT_EQ(rx.outputs()[i].channel, outputs[i].channel) << i;
    ASSERT_EQ(rx.outputs()[i].time, outputs[i].time) << i;
    ASSERT_EQ(rx.outputs()[i].data, outputs[i].data) << i;
  }
}

TEST(SelectSource, OnePlaceDecides) {
  EXPECT_EQ(select_source(true, wrench_t::SOURCE_STATION_KEEP, wrench_t::SOURCE_MANUAL_DEMAND),
            wrench_t::SOURCE_STATION_KEEP);
  EXPECT_EQ(select_source(false, wrench_t::SOURCE_STATION_KEEP, wrench_t::SOURCE_MANUAL_DEMAND),
            wrench_t::SOURCE_MANUAL_DEMAND);
  EXPECT_EQ(select_source(true, wrench_t::SOURCE_NONE, wrench_t::SOURCE_MANUAL_DEMAND),
            wrench_t::SOURCE_NONE);
}

TEST(MixerConfig, EveryPresetConfigLoadsFromAnyDirectory) {
  const auto here = std::filesystem::current_path();
  std::filesystem::current_path("/");
  for (const char* v : {"seed000_rov4", "seed001_rov6", "seed004_usv_x", "seed004_usv_x_table",
                        "seed004_usv_h", "otter", "wamv", "seed001_rov6_table"}) {
    MixerNode node(kSrc + "/config/mixer/" + v + ".yaml");
    EXPECT_EQ(node.allocator().vehicle().name, v);
    EXPECT_EQ(node.params().rate_hz, 50.0);
  }
  std::filesystem::current_path(here);
}

TEST(MixerConfig, BadFilesNameTheKey) {
  const auto dir = std::filesystem::temp_directory_path() / "tiller_mixer_cfg";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& text) {
    const auto p = (dir / "m.yaml").string();
    std::ofstream(p) << text;
    return p;
  };
  auto error_of = [](const std::string& path) -> std::string {
    try {
      MixerNode n(path);
    } catch (const config::Error& e) {
      return e.what();
    }
    return "(no error)";
  };
  std::string e = error_of(write("vehicle: nowhere.yaml\n"));
  EXPECT_NE(e.find("vehicle"), std::string::npos) << e;
  EXPECT_NE(e.find("not found"), std::string::npos) << e;
  e = error_of(write("vehicle: " + kSrc + "/config/vehicles/otter.yaml\nrate_hz: 0\n"));
  EXPECT_NE(e.find("rate_hz"), std::string::npos) << e;
  e = error_of(
      write("vehicle: " + kSrc + "/config/vehicles/otter.yaml\nfallback_source: joystick\n"));
  EXPECT_NE(e.find("fallback_source"), std::string::npos) << e;
  e = error_of(write("vehicle: " + kSrc + "/config/vehicles/otter.yaml\nrate: 5\n"));
  EXPECT_NE(e.find("rate"), std::string::npos) << e;
  // A path from the repository root, from a config inside the tree, from any directory.
  {
    const auto tree = dir / "tree";
    std::filesystem::create_directories(tree / "config/mixer");
    std::filesystem::create_directories(tree / "config/vehicles");
    std::filesystem::copy_file(kSrc + "/config/vehicles/otter.yaml",
                               tree / "config/vehicles/otter.yaml",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string cfg = (tree / "config/mixer/m.yaml").string();
    std::ofstream(cfg) << "vehicle: config/vehicles/otter.yaml\n";
    const auto here = std::filesystem::current_path();
    std::filesystem::current_path("/");
    EXPECT_EQ(error_of(cfg), "(no error)");
    std::filesystem::current_path(here);
  }
  // Absolute vehicle path: fine from anywhere.
  EXPECT_EQ(error_of(write("vehicle: " + kSrc + "/config/vehicles/otter.yaml\n")), "(no error)");
}

// Issue 12, finding 7: a disarmed mixer is a normal state. Its heartbeat said STATE_FAULT
// whenever it was disarmed; now OK (with the reason in the status), DEGRADED only while an
// armed vehicle has no good input.
TEST_F(MixerTest, DisarmedHeartbeatIsOkNotFault) {
  std::vector<heartbeat_t> beats;
  ex->observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch != node->heartbeat_channel()) return;
    heartbeat_t h;
    ASSERT_EQ(h.decode(d, 0, n), n);
    beats.push_back(h);
  });
  manual(5'000, 0, 0);
  ex->run_until(3'500'000);
  ASSERT_GE(beats.size(), 3u);
  for (const auto& h : beats) {
    EXPECT_EQ(h.state, heartbeat_t::STATE_OK) << h.status;
    EXPECT_NE(h.status.find("disarmed"), std::string::npos) << h.status;
  }
}

// The gate's TEST state through the mixer (docs/safety.md, "Thruster test"): one thruster at the
// request's command, every other 0, the request accepted only from the cockpit; a bad request or
// silence ends it at once.
TEST_F(MixerTest, ThrusterTestSpinsOneThrusterAndEndsOnABadRequestOrSilence) {
  const auto* senders = node->allowed_senders(channels::kThrusterTest);
  ASSERT_NE(senders, nullptr);
  EXPECT_EQ(*senders, std::vector<std::string>{"cockpit"});
  auto test = [&](TimeUs at, double cmd, std::int64_t id = 5, bool active = true) {
    thruster_test_t t{};
    t.utime = at;
    t.test_id = id;
    t.active = active;
    t.thruster = 2;
    t.command = cmd;
    t.source = "cockpit";
    ex->inject(channels::kThrusterTest, t, at);
  };
  arm(5'000);  // a centred stick: ACTIVE
  ex->run_until(10'000);
  test(11'000, -0.12);  // a new press is answered at once
  ex->run_until(11'000);
  ASSERT_EQ(seen.back().t, 11'000);
  EXPECT_EQ(seen.back().cmd.gate, thruster_command_t::GATE_TEST);
  EXPECT_TRUE(seen.back().cmd.armed);
  EXPECT_EQ(seen.back().cmd.command, (std::vector<double>{0, 0, -0.12, 0}));
  EXPECT_EQ(seen.back().cmd.hold, "thruster test: thruster 2 at -0.12");
  EXPECT_EQ(node->counter_value("thruster_test.started"), 1);
  test(111'000, -0.12);
  ex->run_until(200'000);
  EXPECT_EQ(seen.back().cmd.command, (std::vector<double>{0, 0, -0.12, 0}));
  test(201'000, 0.9);  // mid-press beyond the mixer's cap (0.15): the test ends at once
  ex->run_until(201'000);
  ASSERT_EQ(seen.back().t, 201'000);
  EXPECT_EQ(seen.back().cmd.gate, thruster_command_t::GATE_WAIT_NEUTRAL);
  EXPECT_TRUE(neutral(seen.back().cmd));
  EXPECT_EQ(node->counter_value("rejected.thruster_test.invalid"), 0);  // a valid message
  // A new press beyond the mixer's cap (0.15) is refused by the gate, with the reason.
  manual(210'000, 0, 0);
  test(211'000, 0.2, 6);
  ex->run_until(211'000);
  EXPECT_EQ(seen.back().cmd.hold,
            "thruster test refused: command beyond thruster_test.max_command");
  EXPECT_TRUE(neutral(seen.back().cmd));
  // A press held, then silent: neutral once the request is older than request_s (0.5 s).
  test(300'000, 0.1, 7);
  arm(300'000);  // the ESC's arm state, fresh (its own 0.5 s limit)
  arm(600'000);
  ex->run_until(780'000);
  EXPECT_EQ(seen.back().cmd.gate, thruster_command_t::GATE_TEST);
  ex->run_until(820'000);
  EXPECT_NE(seen.back().cmd.gate, thruster_command_t::GATE_TEST);
  EXPECT_TRUE(neutral(seen.back().cmd));
}

}  // namespace
}  // namespace tiller
