// BlueESC/tgy I2C backend against the fake bus and the tgy register model: exact bytes, ESC
// arming on zero, the ESC's own timeout, NACKs per ESC, missing ESCs, shutdown, telemetry.
#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>

#include <tiller/arm_state_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/esc_telemetry_t.hpp>
#include <tiller/heartbeat_t.hpp>

#include "esc/tgy_backend.hpp"
#include "esc_rig.hpp"

namespace tiller::test {
namespace {

using esc::fake::TgyEscModel;
using i2c::Transaction;
using Bytes = std::vector<std::uint8_t>;

TEST(Tgy, StartWritesZeroAndArmsEveryEsc) {
  Rig r(tgy_yaml());
  r.bus.record(true);
  for (auto& [a, m] : r.tgy) EXPECT_FALSE(m->armed()) << a;  // powered up, not armed
  const auto rep = r.node->start(0);
  EXPECT_TRUE(rep.all_present) << rep.message;
  const auto& log = r.bus.log();
  ASSERT_EQ(log.size(), 8u);  // per ESC: [00 00 00], then the 9-byte read from 0x02
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(log[2 * i].addr, 0x29 + i);
    EXPECT_EQ(log[2 * i].wrote, (Bytes{0x00, 0x00, 0x00}));
    EXPECT_TRUE(log[2 * i + 1].read);
    EXPECT_EQ(log[2 * i + 1].wrote, (Bytes{0x02}));
    EXPECT_EQ(log[2 * i + 1].read_n, 9u);
  }
  for (auto& [a, m] : r.tgy) {
    EXPECT_TRUE(m->armed()) << a;
    EXPECT_EQ(m->output(), 0);
  }
}

TEST(Tgy, ExactBytesForKnownCommands) {
  Rig r(tgy_yaml("", /*telemetry=*/false));
  r.arm(true);
  r.run_until(0);
  r.bus.record(true);
  r.command({0.5, -1.0, 0.25, 0.0});
  r.run_until(10'000);
  const auto& log = r.bus.log();
  // One write per ESC at once on the command (t = 0, armed), then the same again on the 10 ms
  // cycle; nothing else.
  ASSERT_EQ(log.size(), 8u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(log[k + 4].addr, log[k].addr);
    EXPECT_EQ(log[k + 4].wrote, log[k].wrote);
  }
  // 0.5 -> round(16383.5) = 16384 = 0x4000, big-endian after the register byte.
  EXPECT_EQ(log[0].addr, 0x29);
  EXPECT_EQ(log[0].wrote, (Bytes{0x00, 0x40, 0x00}));
  // -1 -> -32767 = 0x8001.
  EXPECT_EQ(log[1].addr, 0x2a);
  EXPECT_EQ(log[1].wrote, (Bytes{0x00, 0x80, 0x01}));
  // back_left is reversed in the vehicle file: +0.25 -> -0.25 -> -8192 = 0xE000.
  EXPECT_EQ(log[2].addr, 0x2b);
  EXPECT_EQ(log[2].wrote, (Bytes{0x00, 0xE0, 0x00}));
  EXPECT_EQ(log[3].addr, 0x2c);
  EXPECT_EQ(log[3].wrote, (Bytes{0x00, 0x00, 0x00}));
  // The model decoded them as the ESC would.
  EXPECT_EQ(r.tgy[0x29]->output(), 16384);
  EXPECT_EQ(r.tgy[0x2a]->output(), -32767);
  EXPECT_EQ(r.tgy[0x2b]->output(), -8192);
  EXPECT_EQ(r.tgy[0x2c]->output(), 0);
  // And the output message says the same.
  const auto o = r.output();
  EXPECT_EQ(o.backend, "i2c_tgy");
  EXPECT_EQ(o.value, (std::vector<std::int32_t>{16384, -32767, -8192, 0}));
  EXPECT_EQ(o.channel, (std::vector<std::int32_t>{0x29, 0x2a, 0x2b, 0x2c}));
}

TEST(Tgy, CommandBetweenCyclesIsWrittenAtOnceWithoutATelemetryRead) {
  // write_on_command: 3 ms after a cycle, a new command puts exactly one [0x00 hi lo] per ESC on
  // the bus at that instant; the telemetry read stays on the cycle (round robin).
  Rig r(tgy_yaml("disarm_on_timeout: false\n"));
  r.arm(true);
  r.run_until(10'000);
  r.bus.record(true);
  r.run_until(13'000);
  r.command({0.5, 0.0, 0.0, -1.0});
  const auto& log = r.bus.log();
  ASSERT_EQ(log.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_FALSE(log[i].read);
    EXPECT_EQ(log[i].addr, 0x29 + i);
  }
  EXPECT_EQ(log[0].wrote, (Bytes{0x00, 0x40, 0x00}));
  EXPECT_EQ(log[3].wrote, (Bytes{0x00, 0x80, 0x01}));
  EXPECT_EQ(r.tgy[0x29]->output(), 16384);
  r.run_until(20'000);  // the cycle: 4 writes + one telemetry read
  ASSERT_EQ(log.size(), 9u);
  int reads = 0;
  for (std::size_t i = 4; i < 9; ++i) reads += log[i].read ? 1 : 0;
  EXPECT_EQ(reads, 1);
}

TEST(Tgy, FullScaleBothWays) {
  EXPECT_EQ(esc::throttle_from_normalized(1.0), 32767);
  EXPECT_EQ(esc::throttle_from_normalized(-1.0), -32767);
  EXPECT_EQ(esc::throttle_from_normalized(0.0), 0);
  EXPECT_EQ(esc::throttle_from_normalized(2.0), 32767);  // clamped
  EXPECT_EQ(esc::throttle_from_normalized(NAN), 0);
  EXPECT_DOUBLE_EQ(esc::normalized_from_throttle(-32767), -1.0);
}

TEST(Tgy, EscModelNeedsZeroBeforeItRunsAndStopsWithoutCommands) {
  // The model itself, as the firmware behaves: the ESC acts on the low byte, runs only after a
  // zero throttle, and with no command for 4.5 s stops and needs a zero again.
  i2c::FakeBus bus;
  TgyEscModel m;
  bus.attach(0x29, &m);
  const Bytes run{0x00, 0x20, 0x00};  // 8192
  const Bytes zero{0x00, 0x00, 0x00};
  EXPECT_EQ(bus.write(0x29, run.data(), 3), 0);
  EXPECT_EQ(m.throttle(), 8192);
  EXPECT_EQ(m.output(), 0);  // not armed: a non-zero throttle does nothing
  bus.write(0x29, zero.data(), 3);
  EXPECT_TRUE(m.armed());
  bus.write(0x29, run.data(), 3);
  EXPECT_EQ(m.output(), 8192);
  // The high byte alone changes nothing; the low byte completes the value.
  const Bytes hi_only{0x00, 0x10};
  bus.write(0x29, hi_only.data(), 2);
  EXPECT_EQ(m.output(), 8192);
  const Bytes lo_only{0x01, 0x00};
  bus.write(0x29, lo_only.data(), 2);
  EXPECT_EQ(m.output(), 4096);
  bus.set_time(4'400'000);
  EXPECT_EQ(m.output(), 4096);
  bus.set_time(4'600'000);  // > 4.5 s since the last throttle
  EXPECT_EQ(m.output(), 0);
  EXPECT_FALSE(m.armed());
  bus.write(0x29, run.data(), 3);
  EXPECT_EQ(m.output(), 0);  // needs a zero again
  bus.write(0x29, zero.data(), 3);
  bus.write(0x29, run.data(), 3);
  EXPECT_EQ(m.output(), 8192);
  // Nothing at another address.
  EXPECT_EQ(bus.write(0x30, zero.data(), 3), ENXIO);
}

TEST(Tgy, NodeKeepsAnEscAliveThroughItsOwnTimeout) {
  // Disarmed and without commands for 10 s, the node still writes zero every cycle, so the ESCs
  // stay armed and run as soon as the pilot arms.
  Rig r(tgy_yaml());
  r.run_until(10'000'000);
  for (auto& [a, m] : r.tgy) {
    EXPECT_TRUE(m->armed()) << a;
    EXPECT_EQ(m->throttle_writes(), 1001 + 1) << a;  // start + 1001 cycles
  }
  r.arm(true);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(10'010'000);
  EXPECT_EQ(r.tgy[0x29]->output(), 16384);
}

TEST(Tgy, PowerCycledEscWaitsForNeutral) {
  Rig r(tgy_yaml("disarm_on_timeout: false\n"));
  r.arm(true);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(10'000);
  r.tgy[0x29]->power_cycle();  // brown-out on one ESC
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(20'000);
  EXPECT_EQ(r.tgy[0x29]->output(), 0);  // hears 16384 but has not heard zero
  EXPECT_EQ(r.tgy[0x2a]->output(), 16384);
  r.command({0.0, 0.0, 0.0, 0.0});
  r.run_until(30'000);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(40'000);
  EXPECT_EQ(r.tgy[0x29]->output(), 16384);
}

TEST(Tgy, NackOnOneEscIsCountedAndOthersKeepGoing) {
  Rig r(tgy_yaml("disarm_on_timeout: false\n", /*telemetry=*/false));
  r.arm(true);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(0);
  const auto writes0 = r.tgy[0x2c]->throttle_writes();
  r.bus.fail(0x2a, EREMOTEIO, 3);  // front_left NACKs three times
  r.bus.fail(0x2b, ETIMEDOUT, 1);
  r.bus.fail(0x2c, EAGAIN, 1);  // arbitration lost
  r.run_until(50'000);          // five cycles
  const auto& b = r.node->backend();
  EXPECT_EQ(b.stats(0).write_errors, 0);
  EXPECT_EQ(b.stats(1).write_errors, 3);
  EXPECT_EQ(b.stats(1).last_errno, EREMOTEIO);
  EXPECT_EQ(b.stats(2).write_errors, 1);
  EXPECT_EQ(b.stats(2).last_errno, ETIMEDOUT);
  EXPECT_EQ(b.stats(3).write_errors, 1);
  EXPECT_EQ(b.stats(3).last_errno, EAGAIN);
  EXPECT_EQ(r.tgy[0x29]->throttle_writes() - writes0, 5);  // every cycle
  EXPECT_EQ(r.tgy[0x2c]->throttle_writes() - writes0, 4);
  EXPECT_EQ(r.tgy[0x2a]->throttle_writes() - writes0, 2);  // retried, got through twice
  EXPECT_EQ(r.tgy[0x2a]->output(), 16384);
  r.run_until(100'000);
  const auto st = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(st.write_errors, (std::vector<std::int64_t>{0, 3, 1, 1}));
  EXPECT_EQ(st.last_errno, (std::vector<std::int32_t>{0, EREMOTEIO, ETIMEDOUT, EAGAIN}));
  EXPECT_EQ(st.present, (std::vector<std::int8_t>{1, 1, 1, 1}));
  EXPECT_EQ(st.backend, "i2c_tgy");
  EXPECT_EQ(st.bus, "fake-i2c");
  EXPECT_EQ(r.node->counter_value("bus.errors"), 5);
}

TEST(Tgy, PersistentBusErrorShowsInHeartbeat) {
  Rig r(tgy_yaml("disarm_on_timeout: false\n"));
  r.run_until(0);  // started, every ESC answered
  r.bus.fail(0x2b, EIO, -1);
  r.run_until(1'000'000);
  const auto hb = r.cap.last<heartbeat_t>(r.node->heartbeat_channel());
  EXPECT_EQ(hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(hb.status.find("bus errors on back_left (0x2b): EIO"), std::string::npos) << hb.status;
  r.bus.clear_fault(0x2b);
  r.run_until(2'000'000);
  const auto hb2 = r.cap.last<heartbeat_t>(r.node->heartbeat_channel());
  EXPECT_EQ(hb2.state, heartbeat_t::STATE_OK) << hb2.status;
  EXPECT_EQ(hb2.status, "disarmed: neutral");
}

TEST(Tgy, MissingEscAtStartIsNamedAndRetried) {
  Rig r(tgy_yaml("missing_esc: degraded\n"));
  r.bus.detach(0x2b);
  const auto rep = r.node->start(0);
  EXPECT_FALSE(rep.all_present);
  EXPECT_NE(rep.message.find("back_left"), std::string::npos) << rep.message;
  EXPECT_NE(rep.message.find("0x2b"), std::string::npos) << rep.message;
  EXPECT_NE(rep.message.find("ENXIO"), std::string::npos) << rep.message;
  EXPECT_EQ(rep.message.find("front_left"), std::string::npos) << rep.message;
  r.run_until(100'000);
  auto st = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(st.present, (std::vector<std::int8_t>{1, 1, 0, 1}));
  auto hb = r.cap.last<heartbeat_t>(r.node->heartbeat_channel());
  EXPECT_EQ(hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(hb.status.find("ESC missing: back_left (0x2b)"), std::string::npos) << hb.status;
  // The others run; the missing one is written every cycle and found when plugged in.
  r.arm(true);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(110'000);
  EXPECT_EQ(r.tgy[0x29]->output(), 16384);
  r.bus.attach(0x2b, r.tgy[0x2b].get());
  r.command({0.0, 0.0, 0.0, 0.0});
  r.run_until(120'000);
  r.command({0.5, 0.5, 0.5, 0.5});
  r.run_until(200'000);
  st = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(st.present, (std::vector<std::int8_t>{1, 1, 1, 1}));
  EXPECT_EQ(r.tgy[0x2b]->output(), -16384);  // reversed
}

TEST(Tgy, WrongDeviceAtAddressIsNotAnEsc) {
  Rig r(tgy_yaml());
  r.tgy[0x2c]->identifier = 0x00;
  const auto rep = r.node->start(0);
  EXPECT_FALSE(rep.all_present);
  EXPECT_NE(rep.message.find("not 0xAB"), std::string::npos) << rep.message;
}

TEST(Tgy, AllMissingIsAFault) {
  Rig r(tgy_yaml("missing_esc: degraded\n"), /*attach_models=*/false);
  const auto rep = r.node->start(0);
  EXPECT_FALSE(rep.all_present);
  r.run_until(1'000'000);
  const auto hb = r.cap.last<heartbeat_t>(r.node->heartbeat_channel());
  EXPECT_EQ(hb.state, heartbeat_t::STATE_FAULT);
  EXPECT_NE(hb.status.find("no ESC answers on fake-i2c"), std::string::npos) << hb.status;
  EXPECT_EQ(r.node->backend().stats(0).write_errors,
            102);  // start + 101 cycles (0..1 s), each retried
}

TEST(Tgy, ShutdownWritesNeutralToEveryEsc) {
  Rig r(tgy_yaml());
  r.arm(true);
  r.command({0.9, -0.9, 0.9, -0.9});
  r.run_until(50'000);
  for (auto& [a, m] : r.tgy) EXPECT_NE(m->output(), 0) << a;
  r.bus.record(true);
  r.node->shutdown(55'000);
  std::vector<std::uint8_t> seen;
  for (const auto& t : r.bus.log()) {
    if (t.read) continue;
    EXPECT_EQ(t.wrote, (Bytes{0x00, 0x00, 0x00}));
    seen.push_back(t.addr);
  }
  EXPECT_EQ(seen, (std::vector<std::uint8_t>{0x29, 0x2a, 0x2b, 0x2c}));
  for (auto& [a, m] : r.tgy) EXPECT_EQ(m->output(), 0) << a;
  EXPECT_FALSE(r.node->armed());
  const auto st = r.cap.last<arm_state_t>(channels::kArmState);
  EXPECT_FALSE(st.armed);
  EXPECT_NE(st.reason.find("shutdown"), std::string::npos);
  const auto o = r.output();
  EXPECT_EQ(o.value, (std::vector<std::int32_t>{0, 0, 0, 0}));
}

TEST(Tgy, TelemetryDecodingByHand) {
  // pulses 300, voltage raw 0x7F00, temperature raw 49274 (10 kOhm: 25 degC), current raw 32767.
  const std::uint8_t b[9] = {0x01, 0x2C, 0x7F, 0x00, 0xC0, 0x7A, 0x7F, 0xFF, 0xAB};
  const auto raw = esc::decode_tgy_telemetry(b);
  EXPECT_EQ(raw.pulses, 300);
  EXPECT_EQ(raw.voltage, 0x7F00);
  EXPECT_EQ(raw.temperature, 49274);
  EXPECT_EQ(raw.current, 32767);
  EXPECT_EQ(raw.identifier, 0xAB);
  EXPECT_NEAR(esc::tgy_voltage(raw.voltage), 32512.0 / 65536 * 5 * 6.45, 1e-12);  // 16.0 V
  EXPECT_NEAR(esc::tgy_current(raw.current), 0.0, 1e-12);
  EXPECT_NEAR(esc::tgy_current(65535), 5 * 14.706 * 32768.0 / 65535, 1e-9);
  EXPECT_NEAR(esc::tgy_temperature(raw.temperature), 25.0, 0.01);
  EXPECT_TRUE(std::isnan(esc::tgy_temperature(0)));
}

TEST(Tgy, TelemetryRoundRobinThroughTheNode) {
  Rig r(tgy_yaml("disarm_on_timeout: false\n"));
  for (auto& [a, m] : r.tgy) {
    m->volts = 15.2;
    m->amps = 3.5;
    m->temperature_c = 41.0;
  }
  r.node->start(0);
  r.arm(true);
  r.bus.record(true);
  r.command({0.5, -0.5, 0.5, 1.0});
  r.run_until(30'000);
  // One read per cycle, ESC after ESC.
  std::vector<std::uint8_t> reads;
  for (const auto& t : r.bus.log()) {
    if (t.read) reads.push_back(t.addr);
  }
  EXPECT_EQ(reads, (std::vector<std::uint8_t>{0x29, 0x2a, 0x2b, 0x2c}));
  // Over 2 s, each ESC's RPM averages to the model's (0.5 -> 1900 rpm).
  r.bus.record(false);
  double sum = 0;
  int n = 0;
  for (TimeUs t = 40'000; t <= 2'000'000; t += 10'000) {
    r.command({0.5, -0.5, 0.5, 1.0});
    r.run_until(t);
    const auto& tel = r.node->backend().telemetry(0);
    if (tel.sample_utime == t) {
      sum += tel.rpm;
      ++n;
    }
  }
  ASSERT_EQ(n, 50);  // every 4th cycle, 40 ms .. 2 s
  EXPECT_NEAR(sum / n, 1900.0, 40.0);
  const auto m = r.cap.last<esc_telemetry_t>(channels::kEscTelemetry);
  ASSERT_EQ(m.n_escs, 4);
  EXPECT_EQ(m.names[0], "front_right");
  EXPECT_EQ(m.address[3], 0x2c);
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(m.alive[i]);
    EXPECT_NEAR(m.voltage[i], 15.2, 1e-3);
    EXPECT_NEAR(m.current[i], 3.5, 2e-3);
    EXPECT_NEAR(m.temperature[i], 41.0, 0.05);
    EXPECT_GT(m.sample_utime[i], 1'900'000);
  }
  EXPECT_LT(m.rpm[1], -1500);  // commanded negative
  EXPECT_LT(m.rpm[2], -1500);  // reversed: the ESC turns backwards
  EXPECT_GT(m.rpm[3], 3000);   // full: 3800
}

TEST(Tgy, PulsesAreClearedOnRead) {
  i2c::FakeBus bus;
  TgyEscModel m;
  bus.attach(0x29, &m);
  const Bytes zero{0x00, 0x00, 0x00}, full{0x00, 0x7F, 0xFF};
  bus.write(0x29, zero.data(), 3);
  bus.write(0x29, full.data(), 3);
  bus.set_time(1'000'000);  // 1 s at 3800 rpm, 14 poles: 886.67 pulses
  const std::uint8_t reg = 0x02;
  std::uint8_t b[9];
  ASSERT_EQ(bus.write_read(0x29, &reg, 1, b, 9), 0);
  EXPECT_EQ((b[0] << 8) | b[1], 886);
  EXPECT_EQ(b[8], 0xAB);
  ASSERT_EQ(bus.write_read(0x29, &reg, 1, b, 9), 0);
  EXPECT_EQ((b[0] << 8) | b[1], 0);  // cleared by the first read
  // Pointer auto-increment: a 2-byte read from 0x09 gives current low byte then 0xAB.
  const std::uint8_t reg9 = 0x09;
  std::uint8_t two[2];
  ASSERT_EQ(bus.write_read(0x29, &reg9, 1, two, 2), 0);
  EXPECT_EQ(two[1], 0xAB);
}

}  // namespace
}  // namespace tiller::test
