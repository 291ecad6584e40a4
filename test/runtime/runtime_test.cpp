// Node runtime: lockstep order and determinism, replay identity, malformed input, heartbeats.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string_view>

#include <tiller/heartbeat_t.hpp>

#include "echo_node.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/log.hpp"
#include "runtime/replay.hpp"

namespace tiller {
namespace {

using test::ToyController;
using test::ToyPlant;

std::vector<Event> run_closed_loop(TimeUs end, const std::string& log_path = "") {
  ToyController c;
  ToyPlant p;
  LockstepExecutor ex(0);
  ex.add(p);
  ex.add(c);
  std::vector<Event> all;
  std::unique_ptr<LogWriter> log;
  if (!log_path.empty()) log = std::make_unique<LogWriter>(log_path);
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    all.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
    if (log) log->write(ch, d, n, t);
  });
  ex.run_until(end);
  return all;
}

TEST(Lockstep, ClosedLoopConvergesAndIsDeterministic) {
  const auto a = run_closed_loop(30 * kUsPerSecond);
  const auto b = run_closed_loop(30 * kUsPerSecond);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].channel, b[i].channel);
    ASSERT_EQ(a[i].time, b[i].time);
    ASSERT_EQ(a[i].data, b[i].data) << "event " << i;
  }
  // The toy loop is a PI position controller on a damped mass: it must settle at x = 1.
  odometry_t last{};
  for (auto it = a.rbegin(); it != a.rend(); ++it) {
    if (it->channel == "TILLER_ODOMETRY") {
      ASSERT_TRUE(decode(*it, last));
      break;
    }
  }
  EXPECT_NEAR(last.position[0], 1.0, 0.01);
}

TEST(Lockstep, TicksOnGridAndTicksBeforeDeliveries) {
  ToyController c(20'000);
  ToyPlant p(10'000);
  LockstepExecutor ex(5'000);  // starts off-grid: first ticks at 10 ms and 20 ms
  ex.add(p);
  ex.add(c);
  std::vector<Event> seen;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    seen.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
  });
  ex.run_until(40'000);
  EXPECT_EQ(ex.now(), 40'000);
  std::vector<TimeUs> plant_ticks, ctrl_ticks;
  for (const auto& e : seen) {
    if (e.channel == "TILLER_ODOMETRY") plant_ticks.push_back(e.time);
    if (e.channel == "TILLER_WRENCH_VELOCITY") ctrl_ticks.push_back(e.time);
  }
  EXPECT_EQ(plant_ticks, (std::vector<TimeUs>{10'000, 20'000, 30'000, 40'000}));
  EXPECT_EQ(ctrl_ticks, (std::vector<TimeUs>{20'000, 40'000}));
  // At 20 ms the controller ticked before the plant's 20 ms odometry was delivered, so it saw
  // the 10 ms odometry: time since last receipt is 10 ms.
  wrench_t w{};
  for (const auto& e : seen) {
    if (e.channel == "TILLER_WRENCH_VELOCITY" && e.time == 20'000) {
      ASSERT_TRUE(decode(e, w));
    }
  }
  EXPECT_DOUBLE_EQ(w.tau[5], 0.010);
}

TEST(Lockstep, InjectedMessagesArriveAtTheirTime) {
  ToyController c;
  LockstepExecutor ex(0);
  ex.add(c);
  odometry_t o{};
  o.position[0] = 0.25;
  ex.inject("TILLER_ODOMETRY", o, 30'000);
  ex.run_until(30'000);
  EXPECT_EQ(c.received(), 1);
  EXPECT_DOUBLE_EQ(c.x_, 0.25);
  EXPECT_EQ(c.last_rx_, 30'000);
}

TEST(Replay, ReplayOfLockstepLogReproducesOutputsBitForBit) {
  const std::string path = ::testing::TempDir() + "/replay_identity.lcmlog";
  const auto recorded = run_closed_loop(20 * kUsPerSecond, path);
  const auto log = read_log(path);
  ASSERT_EQ(log.size(), recorded.size());

  ToyController c;
  ReplayExecutor rx(c);
  rx.run(log);
  std::vector<const Event*> expected;
  for (const auto& e : recorded) {
    if (e.channel == "TILLER_WRENCH_VELOCITY" || e.channel == c.heartbeat_channel()) {
      expected.push_back(&e);
    }
  }
  const auto& got = rx.outputs();
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].channel, expected[i]->channel) << i;
    ASSERT_EQ(got[i].time, expected[i]->time) << i;
    ASSERT_EQ(got[i].data, expected[i]->data) << "output " << i << " at " << got[i].time;
  }
  std::filesystem::remove(path);
}

TEST(Replay, ChangedLogicIsDetected) {
  const auto recorded = run_closed_loop(2 * kUsPerSecond);
  ToyController c;
  c.integral_ = 0.5;  // a different starting state stands in for a changed gain
  ReplayExecutor rx(c);
  rx.run(recorded);
  bool differs = false;
  std::size_t j = 0;
  for (const auto& e : recorded) {
    if (e.channel != "TILLER_WRENCH_VELOCITY") continue;
    while (j < rx.outputs().size() && rx.outputs()[j].channel != e.channel) ++j;
    ASSERT_LT(j, rx.outputs().size());
    differs |= rx.outputs()[j].data != e.data;
    ++j;
  }
  EXPECT_TRUE(differs);
}

TEST(Node, MalformedAndNonFiniteInputsAreCountedAndDropped) {
  ToyController c;
  LockstepExecutor ex(0);
  ex.add(c);
  Event garbage{"TILLER_ODOMETRY", 10'000, {1, 2, 3, 4, 5}};
  ex.inject(garbage);
  odometry_t bad{};
  bad.position[0] = std::numeric_limits<double>::quiet_NaN();
  ex.inject("TILLER_ODOMETRY", bad, 15'000);
  odometry_t good{};
  good.position[0] = 0.5;
  ex.inject("TILLER_ODOMETRY", good, 25'000);
  ex.run_until(30'000);
  EXPECT_EQ(c.received(), 3);
  EXPECT_EQ(c.rejected(), 2);
  EXPECT_EQ(c.counter_value("malformed.TILLER_ODOMETRY"), 1);
  EXPECT_EQ(c.counter_value("rejected.odometry.nan"), 1);
  EXPECT_DOUBLE_EQ(c.x_, 0.5);
}

TEST(Node, HeartbeatAtOneHertzWithCounters) {
  ToyController c;
  LockstepExecutor ex(0);
  ex.add(c);
  std::vector<heartbeat_t> beats;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    if (ch != "TILLER_HEARTBEAT_TOY_CONTROLLER") return;
    heartbeat_t h;
    ASSERT_EQ(h.decode(d, 0, n), n);
    beats.push_back(h);
  });
  Event garbage{"TILLER_ODOMETRY", 1'500'000, {0}};
  ex.inject(garbage);
  ex.run_until(3 * kUsPerSecond);
  ASSERT_EQ(beats.size(), 4u);  // t = 0, 1, 2, 3 s
  EXPECT_EQ(beats[0].utime, 0);
  EXPECT_EQ(beats[3].utime, 3 * kUsPerSecond);
  EXPECT_EQ(beats[3].process, "toy-controller");
  EXPECT_EQ(beats[1].rejected, 0);
  EXPECT_EQ(beats[2].rejected, 1);
  EXPECT_EQ(beats[2].received, 1);
  bool found = false;
  for (int i = 0; i < beats[2].n_counters; ++i) {
    if (beats[2].counter_names[i] == "malformed.TILLER_ODOMETRY") {
      EXPECT_EQ(beats[2].counter_values[i], 1);
      found = true;
    }
  }
  EXPECT_TRUE(found);
}

// A node whose handler or tick throws: the base class catches it (any executor), counts it,
// latches FAULT in the heartbeat and carries on; the other nodes keep running.
class Throwing : public Node {
 public:
  Throwing() : Node("throwing", 100'000) {
    subscribe("TILLER_ODOMETRY", &Throwing::on_odometry);
    advertise<wrench_t>("TILLER_WRENCH_VELOCITY");
  }
  void on_odometry(const odometry_t& o, TimeUs) {
    if (o.position[0] > 0.5) throw std::runtime_error("odometry handler broke");
  }
  void on_tick(TimeUs now) override {
    ++ticks;
    if (now >= 2 * kUsPerSecond && now < 3 * kUsPerSecond) throw std::logic_error("tick broke");
  }
  int ticks = 0;
};

TEST(Node, NegativeArrayCountIsMalformedNotAFault) {
  // lcm-gen's decode resizes an array to its count and throws on a negative one: such a packet
  // is counted as malformed, the node does not latch FAULT, and the next good message is used.
  odometry_t a{};
  a.position[0] = 0.25;
  odometry_t b = a;
  b.n_pose_cov = 1;
  b.pose_covariance = {0.0};
  std::vector<std::uint8_t> ea(static_cast<std::size_t>(a.getEncodedSize())),
      eb(static_cast<std::size_t>(b.getEncodedSize()));
  ASSERT_GT(a.encode(ea.data(), 0, static_cast<int>(ea.size())), 0);
  ASSERT_GT(b.encode(eb.data(), 0, static_cast<int>(eb.size())), 0);
  std::size_t k = 0;  // the count's last (big-endian low) byte: the first byte that differs
  while (k < ea.size() && ea[k] == eb[k]) ++k;
  ASSERT_GE(k, 3u);
  for (std::size_t i = k - 3; i <= k; ++i) ea[i] = 0xFF;  // n_pose_cov = -1
  ToyController c;
  LockstepExecutor ex(0);
  ex.add(c);
  ex.inject(Event{"TILLER_ODOMETRY", 10'000, ea});
  odometry_t good{};
  good.position[0] = 0.5;
  ex.inject("TILLER_ODOMETRY", good, 20'000);
  ex.run_until(30'000);
  EXPECT_EQ(c.counter_value("malformed.TILLER_ODOMETRY"), 1);
  EXPECT_EQ(c.counter_value("exception.message"), 0);
  EXPECT_FALSE(c.faulted());
  EXPECT_DOUBLE_EQ(c.x_, 0.5);
}

TEST(Node, ExceptionsAreCountedLatchedAsFaultAndDoNotStopTheExecutor) {
  Throwing t;
  ToyPlant p;
  LockstepExecutor ex(0);
  ex.add(p);
  ex.add(t);
  std::vector<heartbeat_t> hbs;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    heartbeat_t h;
    if (ch == t.heartbeat_channel() && h.decode(d, 0, n) == n) hbs.push_back(h);
  });
  ex.run_until(1'500'000);
  EXPECT_FALSE(t.faulted());
  ASSERT_FALSE(hbs.empty());
  EXPECT_EQ(hbs.back().state, heartbeat_t::STATE_OK);
  ex.run_until(5 * kUsPerSecond);
  EXPECT_EQ(t.ticks, 51);  // every grid point from 0 to 5 s, the 10 that threw included
  EXPECT_EQ(t.counter_value("exception.tick"), 10);
  EXPECT_TRUE(t.faulted());
  EXPECT_NE(t.fault_status().find("tick broke"), std::string::npos);
  EXPECT_EQ(hbs.back().state, heartbeat_t::STATE_FAULT);
  EXPECT_EQ(hbs.back().utime, 5 * kUsPerSecond);
  // The plant kept running and its odometry kept arriving.
  EXPECT_EQ(p.counter_value("exception.tick"), 0);
  odometry_t o{};
  o.position[0] = 1.0;
  ex.inject("TILLER_ODOMETRY", o, 5 * kUsPerSecond + 1);
  const std::int64_t rejected = t.rejected();
  ex.run_until(5 * kUsPerSecond + 2);
  EXPECT_EQ(t.counter_value("exception.message"), 1);
  EXPECT_EQ(t.rejected(), rejected + 1);
}

// Channels reach the node as views: a channel name inside a longer buffer is matched exactly.
TEST(Node, DeliverMatchesAStringViewChannelExactly) {
  ToyController c;
  odometry_t o{};
  o.position[0] = 0.25;
  const Event e = encode("TILLER_ODOMETRY", 0, o);
  const std::string buffer = "TILLER_ODOMETRY_AND_MORE";
  c.deliver(std::string_view(buffer).substr(0, 15), e.data.data(), static_cast<int>(e.data.size()),
            1);
  EXPECT_EQ(c.received(), 1);
  EXPECT_DOUBLE_EQ(c.x_, 0.25);
  c.deliver(buffer, e.data.data(), static_cast<int>(e.data.size()), 2);  // not subscribed
  c.deliver(std::string_view(buffer).substr(0, 14), e.data.data(), static_cast<int>(e.data.size()),
            3);
  EXPECT_EQ(c.received(), 1);
  EXPECT_TRUE(c.subscribes_to(std::string_view(buffer).substr(0, 15)));
  EXPECT_EQ(c.subscribed_type("TILLER_ODOMETRY"), "odometry_t");
}

}  // namespace
}  // namespace tiller
