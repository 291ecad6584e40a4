// EscNode safety logic on the sim backend: start disarmed and neutral, arming rules, mapping by
// name, command timeout, reverse, trim, slew through zero, bad input, 10 Hz messages, lockstep.
#include <gtest/gtest.h>

#include <memory>

#include <algorithm>
#include <cmath>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/heartbeat_t.hpp>

#include "esc_rig.hpp"
#include "runtime/lockstep.hpp"

namespace tiller::test {
namespace {

TEST(EscNode, StartsDisarmedWritingNeutralEveryCycle) {
  Rig r(sim_yaml());
  r.command({0.5, 0.5, 0.5, 0.5});  // the mixer would not do this while disarmed; still neutral
  r.run_until(990'000);
  const auto outs = r.cap.all<esc_output_t>(channels::kEscOutput);
  ASSERT_EQ(outs.size(), 100u);  // 100 Hz, ticks at 0..990 ms
  for (const auto& o : outs) {
    EXPECT_FALSE(o.armed);
    EXPECT_EQ(o.backend, "sim");
    EXPECT_EQ(o.unit, esc_output_t::UNIT_THROTTLE_INT16);
    ASSERT_EQ(o.n_channels, 4);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(o.value[i], 0);
      EXPECT_EQ(o.normalized[i], 0.0);
      EXPECT_EQ(o.names[i], kRov4[i]);
    }
  }
  EXPECT_FALSE(r.node->armed());
  const auto st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_FALSE(st.armed);
}

TEST(EscNode, ArmsOnlyWhileCommandsAreNeutral) {
  Rig r(sim_yaml());
  r.run_until(100'000);
  r.command({0.0, 0.3, 0.0, 0.0});
  r.arm(true, "teleop");
  EXPECT_FALSE(r.node->armed());
  auto st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_FALSE(st.armed);
  EXPECT_NE(st.reason.find("not neutral"), std::string::npos) << st.reason;
  EXPECT_NE(st.reason.find("front_left"), std::string::npos) << st.reason;
  EXPECT_EQ(r.node->counter_value("arm.refused_not_neutral"), 1);

  // Within tolerance (0.02) counts as neutral.
  r.run_until(110'000);
  r.command({0.0, 0.01, -0.02, 0.0});
  r.arm(true, "teleop");
  EXPECT_TRUE(r.node->armed());
  st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_TRUE(st.armed);
  EXPECT_EQ(st.reason, "armed by teleop");

  // A disarm request always disarms, even mid-command, and the next cycle is neutral.
  r.command({0.8, 0.8, 0.8, 0.8});
  r.run_until(120'000);
  EXPECT_EQ(r.output().value[0], std::lround(0.8 * 32767));
  r.arm(false, "teleop");
  EXPECT_FALSE(r.node->armed());
  r.run_until(130'000);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r.output().value[i], 0);
}

// Issue 30, scenario 2, with the clock moved: an arm request captured from one start of
// tiller-esc and replayed into the next is refused by its boot nonce whatever the clocks say,
// also when the receiver's clock stepped back so that the old stamp looks fresh (age 0), and an
// hour either way; the new start's own request arms.
TEST(EscNode, ACapturedArmIsRefusedAfterARestartWhateverTheClock) {
  Rig before(sim_yaml());
  before.node->set_boot_nonce(1111);
  before.next_tick = 7'200'000'000;  // two hours into the clock
  before.run_until(7'200'000'000);
  arm_request_t captured{};
  captured.utime = before.now;
  captured.arm = true;
  captured.source = "teleop";
  captured.boot_nonce = 1111;
  before.send(channels::kArmRequest, captured);
  ASSERT_TRUE(before.node->armed());

  // Restarted (a new nonce), its clock at the stamp (stepped back), an hour later, an hour earlier.
  const auto restarted_at = [](TimeUs now) {
    auto r = std::make_unique<Rig>(sim_yaml());
    r->node->set_boot_nonce(2222);
    r->next_tick = now;  // start its ticks there
    r->run_until(now);
    return r;
  };
  for (const TimeUs now :
       {captured.utime, captured.utime + 3'600'000'000, captured.utime - 3'600'000'000}) {
    auto after = restarted_at(now);
    after->send(channels::kArmRequest, captured);
    EXPECT_FALSE(after->node->armed()) << "at " << now;
    EXPECT_EQ(after->node->counter_value("rejected.arm_request.boot_nonce"), 1) << "at " << now;
  }
  auto after = restarted_at(captured.utime);
  arm_request_t fresh = captured;
  fresh.boot_nonce = 2222;
  after->send(channels::kArmRequest, fresh);
  EXPECT_TRUE(after->node->armed());
}

TEST(EscNode, ArmsWithNoCommandAtAll) {
  // No command yet means the output is neutral: arming is allowed (mixer not yet running).
  Rig r(sim_yaml());
  r.run_until(50'000);
  r.arm(true);
  EXPECT_TRUE(r.node->armed());
}

// A message's own utime (docs/safety.md, "Stale by its own time stamp"): an arm request that
// waited more than 1 s + the clock offset bound (in a stopped process's queue, say) is refused
// with the reason on TILLER_ARM_STATE; a disarm is always taken; a thruster command older than
// the command timeout + the bound by its utime is dropped and counted, and refreshes nothing.
TEST(EscNode, RefusesAnArmRequestOrACommandTooOldByItsUtime) {
  Rig r(sim_yaml());
  r.run_until(3'000'000);
  arm_request_t a{};
  a.arm = true;
  a.source = "teleop";
  a.utime = 3'000'000 - kEventMaxAgeUs - kDefaultClockOffsetUs - 1;
  r.send(channels::kArmRequest, a);
  EXPECT_FALSE(r.node->armed());
  EXPECT_EQ(r.node->counter_value("rejected.arm_request.stale"), 1);
  const auto st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_NE(st.reason.find("stamped -1.250 s"), std::string::npos) << st.reason;
  a.utime += 1;  // exactly 1 s + the bound old: taken
  r.send(channels::kArmRequest, a);
  EXPECT_TRUE(r.node->armed());

  // A command 0.25 s (timeout) + 0.25 s (bound) + 1 us old by its utime: dropped, not written.
  thruster_command_t m{};
  m.armed = true;
  m.arm_allowed = true;
  m.n_thrusters = 4;
  m.names = kRov4;
  m.command = {0.5, 0.5, 0.5, 0.5};
  m.utime = 3'000'000 - 500'001;
  r.send(channels::kThrusterCommand, m);
  EXPECT_EQ(r.node->counter_value("rejected.command.stale"), 1);
  r.run_until(3'010'000);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r.output().value[i], 0);

  a.arm = false;  // a disarm, however old, is taken
  a.utime = 0;
  r.send(channels::kArmRequest, a);
  EXPECT_FALSE(r.node->armed());
}

TEST(EscNode, MapsCommandsByNameNotPosition) {
  Rig r(sim_yaml("disarm_on_timeout: false\n"));
  r.arm(true);
  r.command({0.1, 0.2, 0.4, -0.5}, {"back_right", "front_right", "front_left", "back_left"});
  r.run_until(0);
  const auto o = r.output();
  EXPECT_TRUE(o.armed);
  EXPECT_EQ(o.value[0], std::lround(0.2 * 32767));  // front_right
  EXPECT_EQ(o.value[1], std::lround(0.4 * 32767));  // front_left
  EXPECT_EQ(o.value[2], std::lround(0.5 * 32767));  // back_left is reversed: -(-0.5)
  EXPECT_EQ(o.value[3], std::lround(0.1 * 32767));  // back_right
  EXPECT_NEAR(o.normalized[2], 0.5, 1e-4);
}

TEST(EscNode, ReversedFlipsOnlyItsOwnSign) {
  Rig r(sim_yaml());
  r.arm(true);
  r.command({0.25, 0.25, 0.25, 0.25});
  r.run_until(0);
  const auto o = r.output();
  const auto v = std::lround(0.25 * 32767);
  EXPECT_EQ(o.value[0], v);
  EXPECT_EQ(o.value[1], v);
  EXPECT_EQ(o.value[2], -v);  // back_left: reversed: true in rov4.yaml
  EXPECT_EQ(o.value[3], v);
}

TEST(EscNode, ArmedCommandIsWrittenAtOnceAtMostOncePerInterval) {
  // write_on_command: a changed command while armed goes on the bus at the instant it arrives, not
  // at the next 10 ms cycle, even just after a cycle's write; a burst is held to one extra write
  // per min_write_interval (2 ms), the held-back command going out at the next 2 ms tick;
  // disarmed, nothing extra is written (the cycle's neutral is all there is).
  Rig r(sim_yaml("disarm_on_timeout: false\n"));
  r.run_until(0);
  r.command({0.5, 0.5, 0.5, 0.5});
  EXPECT_EQ(r.cap.all<esc_output_t>(channels::kEscOutput).size(), 1u);  // the tick at 0 only
  r.arm(true);  // not neutral: refused, still only the tick's write
  r.run_until(20'000);
  r.command({0.0, 0.0, 0.0, 0.0});
  r.arm(true);
  ASSERT_TRUE(r.node->armed());
  r.run_until(21'000);
  const std::size_t before = r.cap.all<esc_output_t>(channels::kEscOutput).size();
  r.command({0.25, 0.0, 0.0, 0.0});  // 1 ms after the 20 ms cycle: written at once
  auto outs = r.cap.all<esc_output_t>(channels::kEscOutput);
  ASSERT_EQ(outs.size(), before + 1);
  EXPECT_EQ(outs.back().utime, 21'000);
  EXPECT_TRUE(outs.back().armed);
  EXPECT_EQ(outs.back().value[0], std::lround(0.25 * 32767));
  r.run_until(22'500);
  r.command({0.5, 0.0, 0.0, 0.0});  // 1.5 ms after the last extra write: held back...
  EXPECT_EQ(r.cap.all<esc_output_t>(channels::kEscOutput).size(), before + 1);
  EXPECT_EQ(r.node->tick_period(), 2'000);  // ...to the first 2 ms tick the interval allows
  r.run_until(24'000);
  outs = r.cap.all<esc_output_t>(channels::kEscOutput);
  ASSERT_EQ(outs.size(), before + 2);
  EXPECT_EQ(outs.back().utime, 24'000);
  EXPECT_EQ(outs.back().value[0], std::lround(0.5 * 32767));
  r.run_until(30'000);  // the bus cycle stays on its 10 ms grid
  outs = r.cap.all<esc_output_t>(channels::kEscOutput);
  ASSERT_EQ(outs.size(), before + 3);
  EXPECT_EQ(outs.back().utime, 30'000);
  // The same command again (the mixer's fixed-rate repeat) is left to the cycle.
  r.run_until(35'000);
  r.command({0.5, 0.0, 0.0, 0.0});
  r.run_until(39'000);
  EXPECT_EQ(r.cap.all<esc_output_t>(channels::kEscOutput).size(), before + 3);

  Rig off(sim_yaml("disarm_on_timeout: false\nwrite_on_command: false\n"));
  off.run_until(20'000);
  off.arm(true);
  off.run_until(23'000);
  const std::size_t n = off.cap.all<esc_output_t>(channels::kEscOutput).size();
  off.command({0.25, 0.0, 0.0, 0.0});
  EXPECT_EQ(off.cap.all<esc_output_t>(channels::kEscOutput).size(), n);
}

TEST(EscNode, TimeoutGoesNeutralKeepsWritingAndDisarms) {
  Rig r(sim_yaml());
  r.arm(true);
  r.run_until(1'000'000);
  r.command({0.5, 0.5, 0.5, 0.5});  // at t = 1.000 s
  r.run_until(1'250'000);
  EXPECT_EQ(r.output().value[0], std::lround(0.5 * 32767));  // 250 ms later: still fresh
  EXPECT_TRUE(r.node->armed());
  r.run_until(1'260'000);  // first cycle past the timeout
  for (int i = 0; i < 4; ++i) EXPECT_EQ(r.output().value[i], 0);
  EXPECT_FALSE(r.node->armed());
  EXPECT_EQ(r.node->timeouts(), 1);
  EXPECT_EQ(r.node->stale(), 1);
  const auto st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_NE(st.reason.find("command timeout"), std::string::npos) << st.reason;
  // Neutral keeps being written, every cycle.
  const std::size_t before = r.cap.count(channels::kEscOutput);
  r.run_until(3'260'000);
  EXPECT_EQ(r.cap.count(channels::kEscOutput) - before, 200u);
  EXPECT_EQ(r.output().value[0], 0);
  // A command that comes back does not move a thruster: the node is disarmed.
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(3'270'000);
  EXPECT_EQ(r.output().value[0], 0);
  const auto status = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(status.timeouts, 1);
}

TEST(EscNode, TimeoutWithoutDisarmResumesOnFreshCommand) {
  Rig r(sim_yaml("disarm_on_timeout: false\ncommand_timeout_ms: 100\n"));
  r.arm(true);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(110'000);
  EXPECT_EQ(r.output().value[0], 0);
  EXPECT_TRUE(r.node->armed());
  r.run_until(200'000);
  auto status = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_TRUE(status.command_timeout);
  EXPECT_TRUE(status.armed);
  r.command({-0.5, 0.5, 0.5, 0.5});
  r.run_until(210'000);
  EXPECT_EQ(r.output().value[0], -std::lround(0.5 * 32767));
}

TEST(EscNode, TrimScalesTheOutput) {
  Rig r(sim_yaml("", ", trim: 0.8"));
  r.arm(true);
  r.command({1.0, -1.0, 0.5, 0.0});
  r.run_until(0);
  const auto o = r.output();
  EXPECT_EQ(o.value[0], std::lround(0.8 * 32767));
  EXPECT_EQ(o.value[1], -std::lround(0.8 * 32767));
  EXPECT_EQ(o.value[2], -std::lround(0.4 * 32767));
  EXPECT_EQ(o.value[3], 0);
}

TEST(EscNode, SlewLimitRampsThroughZeroOnReversal) {
  // 10 per second at 100 Hz: at most 0.1 per cycle.
  Rig r(sim_yaml("", ", slew_per_s: 10"));
  r.arm(true);
  r.command({0.3, 0.0, 0.0, 0.0});
  std::vector<double> seen;
  for (TimeUs t = 0; t <= 30'000; t += 10'000) {
    r.run_until(t);
    seen.push_back(r.output().normalized[0]);
  }
  r.command({-0.25, 0.0, 0.0, 0.0});
  for (TimeUs t = 40'000; t <= 100'000; t += 10'000) {
    r.run_until(t);
    seen.push_back(r.output().normalized[0]);
  }
  const std::vector<double> expect = {0.1, 0.2, 0.3, 0.3, 0.2, 0.1, 0.0, -0.1, -0.2, -0.25, -0.25};
  ASSERT_EQ(seen.size(), expect.size());
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_NEAR(seen[k], expect[k], 1e-4) << k;
  // Exactly zero on the bus for the cycle between the two directions (t = 60 ms; the reversed
  // command itself arrived at 30 ms and was written at once, with no time to slew).
  int at_60ms = 0;
  for (const auto& o : r.cap.all<esc_output_t>(channels::kEscOutput)) {
    if (o.utime == 60'000) {
      EXPECT_EQ(o.value[0], 0);
      ++at_60ms;
    }
  }
  EXPECT_EQ(at_60ms, 1);
}

TEST(EscNode, SlewDoesNotDelayDisarm) {
  Rig r(sim_yaml("", ", slew_per_s: 1"));
  r.arm(true);
  for (TimeUs t = 0; t <= 500'000; t += 100'000) {
    r.run_until(t);
    r.command({1.0, 1.0, 1.0, 1.0});
  }
  EXPECT_NEAR(r.output().normalized[0], 0.50, 1e-4);  // 1/s: 50 cycles of 0.01 (10..500 ms)
  r.arm(false);
  r.run_until(510'000);
  EXPECT_EQ(r.output().value[0], 0);
}

TEST(EscNode, BadCommandsAreDroppedAndCounted) {
  Rig r(sim_yaml("disarm_on_timeout: false\n"));
  r.arm(true);
  r.command({0.2, 0.2, 0.2, 0.2});
  r.run_until(0);
  r.command({NAN, 0.9, 0.9, 0.9});
  r.command({0.9, 1.5, 0.9, 0.9});
  r.command({0.9, 0.9, 0.9}, {"front_right", "front_left", "back_left"});
  r.command({0.9, 0.9, 0.9, 0.9, 0.9},
            {"front_right", "front_left", "back_left", "back_right", "up"});
  r.command({0.9, 0.9, 0.9, 0.9}, {"front_right", "front_right", "back_left", "back_right"});
  r.run_until(10'000);
  EXPECT_EQ(r.output().value[0], std::lround(0.2 * 32767));  // still the last good command
  EXPECT_EQ(r.node->counter_value("rejected.command.nan"), 1);
  EXPECT_EQ(r.node->counter_value("rejected.command.range"), 1);
  EXPECT_EQ(r.node->counter_value("rejected.command.missing_thruster"), 2);
  EXPECT_EQ(r.node->counter_value("rejected.command.unknown_thruster"), 1);
  EXPECT_EQ(r.node->rejected(), 5);
  // Garbage bytes on the command channel: counted as malformed, nothing else happens.
  const std::uint8_t junk[5] = {1, 2, 3, 4, 5};
  r.node->deliver(channels::kThrusterCommand, junk, 5, 10'000);
  EXPECT_EQ(r.node->rejected(), 6);
  // A bad command does not refresh the timeout: after 250 ms of only bad commands, neutral.
  for (TimeUs t = 20'000; t <= 300'000; t += 20'000) {
    r.run_until(t);
    r.command({NAN, 0, 0, 0});
  }
  r.run_until(310'000);
  EXPECT_EQ(r.output().value[0], 0);
}

TEST(EscNode, ArmStateOnChangeAndAt10Hz) {
  Rig r(sim_yaml());
  r.run_until(990'000);
  EXPECT_EQ(r.cap.count(channels::kArmState), 10u);  // 0, 100, ..., 900 ms
  EXPECT_EQ(r.cap.count(channels::kEscStatus), 10u);
  EXPECT_EQ(r.cap.count(channels::kEscTelemetry), 10u);
  r.arm(true);
  EXPECT_EQ(r.cap.count(channels::kArmState), 11u);  // at once on change
  const auto hb = r.cap.last<heartbeat_t>(r.node->heartbeat_channel());
  EXPECT_EQ(hb.process, "esc");
  EXPECT_EQ(r.node->heartbeat_channel(), "TILLER_HEARTBEAT_ESC");
}

TEST(EscNode, RunsInLockstepAndIsDeterministic) {
  auto run = [] {
    EscNode esc(parse_config(sim_yaml()).node, esc::make_backend(parse_config(sim_yaml())));
    LockstepExecutor ex(0);
    ex.add(esc);
    arm_request_t a{};
    a.arm = true;
    a.source = "test";
    ex.inject(channels::kArmRequest, a, 5'000);
    for (int k = 0; k < 50; ++k) {
      thruster_command_t c{};
      c.utime = 10'000 + k * 20'000;
      c.armed = true;
      c.n_thrusters = 4;
      c.names = kRov4;
      c.command = {std::sin(k * 0.1), 0.5, -0.5, 0.0};
      ex.inject(channels::kThrusterCommand, c, c.utime);
    }
    std::vector<Event> seen;
    ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
      if (ch == channels::kEscOutput) seen.push_back(Event{ch, t, {d, d + n}});
    });
    ex.run_until(2'000'000);
    return seen;
  };
  const auto a = run();
  const auto b = run();
  // 201 cycles (0..2 s at 100 Hz) + 50 commands written at once (armed, write_on_command).
  ASSERT_EQ(a.size(), 251u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(a[k].data, b[k].data);
  esc_output_t o;
  const auto at_half =
      std::find_if(a.begin(), a.end(), [](const Event& e) { return e.time == 500'000; });
  ASSERT_NE(at_half, a.end());
  ASSERT_TRUE(decode(*at_half, o));  // t = 0.5 s: armed and commanded
  EXPECT_TRUE(o.armed);
  EXPECT_EQ(o.value[1], std::lround(0.5 * 32767));
  EXPECT_EQ(o.value[2], std::lround(0.5 * 32767));  // reversed
  ASSERT_TRUE(decode(a.back(), o));                 // last command at 0.99 s: timed out, neutral
  EXPECT_FALSE(o.armed);
  EXPECT_EQ(o.value[1], 0);
}

}  // namespace
}  // namespace tiller::test
