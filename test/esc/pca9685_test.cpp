// PCA9685 PWM backend against the fake bus and the PCA9685 register model: the start-up
// sequence byte by byte, pulse widths, oscillator calibration and external clock, seed 001's
// board channel map (the text, not the code), NACKs, a board that appears late or loses power,
// and shutdown.
#include <gtest/gtest.h>

#include <cerrno>
#include <cmath>

#include <tiller/esc_bus_status_t.hpp>

#include "esc/fake/fake_i2c.hpp"
#include "esc/pca9685_backend.hpp"
#include "esc_rig.hpp"
#include "gpio/output.hpp"

namespace tiller::test {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::string pca_yaml(const std::string& pca_extra = "", const std::string& extra = "") {
  return "vehicle: rov4.yaml\nbackend: pca9685\n" + extra +
         "pca9685: {bus: /dev/i2c-1, address: 0x40, pwm_hz: 50" + pca_extra +
         "}\n"
         "escs:\n"
         "  - {name: front_right, channel: 0}\n"
         "  - {name: front_left, channel: 1}\n"
         "  - {name: back_left, channel: 4}\n"
         "  - {name: back_right, channel: 15, min_us: 1000, neutral_us: 1520, max_us: 2000}\n";
}

esc::EscConfig seed001() {
  return esc::load_esc_config_file(std::string(TILLER_SOURCE_DIR) +
                                   "/config/esc/seed001_pca9685.yaml");
}

// Seed 001's message order [F, LF, RF, B, LB, RB] (its text's setpoint array).
const std::vector<std::string> kRov6 = {"F", "LF", "RF", "B", "LB", "RB"};

TEST(Pca9685, PrescaleAndTick) {
  esc::Pca9685Params p;
  EXPECT_EQ(esc::pca9685::prescale(p), 121);  // round(25e6 / (4096 * 50)) - 1
  EXPECT_NEAR(esc::pca9685::tick_us(p), 4.88, 1e-12);
  p.oscillator_calibration = 1.04;
  EXPECT_EQ(esc::pca9685::prescale(p), 126);  // round(26e6 / 204800) - 1
  p.external_clock_hz = 20e6;
  EXPECT_EQ(esc::pca9685::prescale(p), 97);
}

TEST(Pca9685, StartSequenceExactBytes) {
  Rig r(pca_yaml());
  r.bus.record(true);
  EXPECT_TRUE(r.pca->sleeping());  // power-up state
  const auto rep = r.node->start(0);
  EXPECT_TRUE(rep.all_present) << rep.message;
  const auto& log = r.bus.log();
  ASSERT_EQ(log.size(), 6u + 4u);
  for (const auto& t : log) EXPECT_EQ(t.addr, 0x40);
  EXPECT_EQ(log[0].wrote, (Bytes{0x00, 0x30}));  // MODE1 <- SLEEP | AI
  EXPECT_EQ(log[1].wrote, (Bytes{0xFE, 0x79}));  // PRE_SCALE <- 121, while asleep
  EXPECT_EQ(log[2].wrote, (Bytes{0x01, 0x04}));  // MODE2 <- OUTDRV (totem pole)
  EXPECT_EQ(log[3].wrote, (Bytes{0x00, 0x20}));  // MODE1 <- AI: wake
  EXPECT_EQ(log[4].wrote, (Bytes{0x00, 0xA0}));  // RESTART | AI, after the 500 us wait
  EXPECT_LE(log[3].time + 500, log[4].time);
  EXPECT_TRUE(log[5].read);  // PRE_SCALE read back
  EXPECT_EQ(log[5].wrote, (Bytes{0xFE}));
  EXPECT_EQ(log[5].read_n, 1u);
  // Neutral on every channel: 1500 us / 4.88 us = 307.4 -> 307 = 0x133; back_right's neutral
  // is 1520 us -> 311.5 -> 311 = 0x137. LEDn_ON_L = 0x06 + 4n.
  EXPECT_EQ(log[6].wrote, (Bytes{0x06, 0x00, 0x00, 0x33, 0x01}));
  EXPECT_EQ(log[7].wrote, (Bytes{0x0A, 0x00, 0x00, 0x33, 0x01}));
  EXPECT_EQ(log[8].wrote, (Bytes{0x16, 0x00, 0x00, 0x33, 0x01}));
  EXPECT_EQ(log[9].wrote, (Bytes{0x42, 0x00, 0x00, 0x37, 0x01}));
  EXPECT_EQ(r.bus.waited_us(), 500);
  // The chip is awake, clocked at 50 Hz, sending neutral.
  EXPECT_FALSE(r.pca->sleeping());
  EXPECT_EQ(r.pca->reg(0x00), 0x20);
  EXPECT_EQ(r.pca->reg(0xFE), 0x79);
  EXPECT_NEAR(r.pca->pwm_hz(), 50.03, 0.01);
  EXPECT_NEAR(r.pca->pulse_us(0, r.bus.now()), 307 * 4.88, 1e-9);
  EXPECT_EQ(r.pca->prescale_writes_ignored(), 0);
}

TEST(Pca9685, PulseWidthBytesForKnownCommands) {
  Rig r(pca_yaml("", "disarm_on_timeout: false\n"));
  r.arm(true);
  r.run_until(0);
  r.bus.record(true);
  r.command({1.0, -1.0, -0.5, 0.5});
  r.run_until(10'000);
  const auto& log = r.bus.log();
  // Written at once on the command (armed), then the same 4 writes on the 10 ms cycle.
  ASSERT_EQ(log.size(), 8u);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(log[k + 4].wrote, log[k].wrote);
  EXPECT_EQ(log[0].wrote, (Bytes{0x06, 0x00, 0x00, 0x85, 0x01}));  // 1900 us -> 389 = 0x185
  EXPECT_EQ(log[1].wrote, (Bytes{0x0A, 0x00, 0x00, 0xE1, 0x00}));  // 1100 us -> 225 = 0xE1
  // back_left is reversed: -0.5 -> +0.5 -> 1700 us -> 348.4 -> 348 = 0x15C.
  EXPECT_EQ(log[2].wrote, (Bytes{0x16, 0x00, 0x00, 0x5C, 0x01}));
  // back_right: 1520 + 0.5 (2000 - 1520) = 1760 us -> 360.7 -> 361 = 0x169.
  EXPECT_EQ(log[3].wrote, (Bytes{0x42, 0x00, 0x00, 0x69, 0x01}));
  const auto o = r.output();
  EXPECT_EQ(o.unit, esc_output_t::UNIT_PULSE_US);
  EXPECT_EQ(o.value, (std::vector<std::int32_t>{1900, 1100, 1700, 1760}));
  EXPECT_EQ(o.channel, (std::vector<std::int32_t>{0, 1, 4, 15}));
  EXPECT_NEAR(r.pca->pulse_us(15, r.bus.now()), 361 * 4.88, 1e-9);
}

TEST(Pca9685, Seed001BoardMapFollowsTheTextNotTheCode) {
  // Seed 001's text: Front 1, Left Back 2, Left Front 3, Right Front 8, Right Back 9, Back 11.
  // Its code writes setpoint[1] (Left Front) to channel 1 *and* channel 3, so Front never gets
  // a pulse. Tiller follows the text: each thruster alone moves exactly its own channel.
  const std::map<std::string, int> text = {{"F", 1},  {"LB", 2}, {"LF", 3},
                                           {"RF", 8}, {"RB", 9}, {"B", 11}};
  for (const auto& [name, ch] : text) {
    SCOPED_TRACE(name);
    Rig r(seed001());
    r.arm(true);
    std::vector<double> u(6, 0.0);
    for (std::size_t k = 0; k < 6; ++k) u[k] = kRov6[k] == name ? 0.5 : 0.0;
    r.command(u, kRov6);
    r.run_until(10'000);
    for (int c : {1, 2, 3, 8, 9, 11}) {
      const double want = c == ch ? 348 * 4.88 : 307 * 4.88;  // 1700 us : 1500 us, in counts
      EXPECT_NEAR(r.pca->pulse_us(c, r.bus.now()), want, 1e-9) << "channel " << c;
    }
  }
  // The case the seed's code gets wrong, spelled out: Left Front alone leaves channel 1
  // (Front) at neutral; Front alone moves channel 1 and leaves channel 3 at neutral.
  Rig r(seed001());
  r.arm(true);
  r.command({0.0, 0.5, 0.0, 0.0, 0.0, 0.0}, kRov6);  // LF
  r.run_until(10'000);
  EXPECT_NEAR(r.pca->pulse_us(1, r.bus.now()), 307 * 4.88, 1e-9);
  EXPECT_NEAR(r.pca->pulse_us(3, r.bus.now()), 348 * 4.88, 1e-9);
  r.command({0.5, 0.0, 0.0, 0.0, 0.0, 0.0}, kRov6);  // F
  r.run_until(20'000);
  EXPECT_NEAR(r.pca->pulse_us(1, r.bus.now()), 348 * 4.88, 1e-9);
  EXPECT_NEAR(r.pca->pulse_us(3, r.bus.now()), 307 * 4.88, 1e-9);
}

TEST(Pca9685, OscillatorCalibrationCorrectsAFastChip) {
  // A chip whose oscillator runs 4% fast (26 MHz). Uncalibrated, "1500 us" comes out short
  // enough to turn a thruster; with the measured factor it is back within one count.
  auto pulse_out = [](double calibration) {
    Rig r(pca_yaml(", oscillator_calibration: " + std::to_string(calibration)));
    r.pca->oscillator_hz = 26e6;
    r.node->start(0);
    return r.pca->pulse_us(0, r.bus.now());
  };
  EXPECT_GT(std::abs(pulse_out(1.0) - 1500.0), 50.0);  // 307 * 122 / 26 MHz = 1440.5 us
  EXPECT_LT(std::abs(pulse_out(1.04) - 1500.0), 5.0);  // 307 * 127 / 26 MHz = 1499.6 us
}

TEST(Pca9685, ExternalClockIsSetWhileAsleep) {
  Rig r(pca_yaml(", external_clock_hz: 20000000"));
  r.pca->external_clock_hz = 20e6;
  r.bus.record(true);
  r.node->start(0);
  const auto& log = r.bus.log();
  ASSERT_GE(log.size(), 6u);
  EXPECT_EQ(log[0].wrote, (Bytes{0x00, 0x30}));
  EXPECT_EQ(log[1].wrote, (Bytes{0x00, 0x70}));  // SLEEP | EXTCLK | AI
  EXPECT_EQ(log[2].wrote, (Bytes{0xFE, 0x61}));  // 97
  EXPECT_EQ(log[4].wrote, (Bytes{0x00, 0x60}));  // wake, EXTCLK kept
  EXPECT_EQ(r.pca->reg(0x00) & 0x40, 0x40);
  EXPECT_NEAR(r.pca->pwm_hz(), 20e6 / (4096.0 * 98), 1e-9);
}

// Issue 33: the Navigator's PWM_OE. Outputs stay off (OE high) until a cycle of neutral pulses
// went out to an initialised chip, go off again while the chip is set up after a brown-out, and
// off when the backend goes (tiller-esc exits).
TEST(Pca9685, OutputEnableLowOnlyAfterSafePulsesOnAnInitialisedChip) {
  struct Shared : gpio::OutputLine {  // forwards to a line the test keeps
    explicit Shared(gpio::FakeOutputLine* l) : l_(l) {}
    int set(int v) override { return l_->set(v); }
    int level() const override { return l_->level(); }
    std::string name() const override { return l_->name(); }
    gpio::FakeOutputLine* l_;
  };
  gpio::FakeOutputLine oe(1, "gpiochip0:26");
  i2c::FakeBus bus;
  esc::fake::Pca9685Model chip;
  esc::Pca9685Params p;
  p.external_clock_hz = 24.576e6;  // the Navigator's oscillator
  std::vector<esc::EscChannelParams> escs(2);
  escs[1].address = 1;
  {
    esc::Pca9685Backend b(bus, p, escs);
    b.set_output_enable(std::make_unique<Shared>(&oe));
    EXPECT_EQ(oe.level(), 1);
    // No board: start fails, outputs stay off, and writes do not enable them.
    EXPECT_FALSE(b.start(0).all_present);
    const std::int32_t neutral[2] = {1500, 1500};
    b.write(neutral, 10'000);
    EXPECT_EQ(oe.level(), 1);
    EXPECT_FALSE(b.outputs_enabled());
    // The board answers: start() initialises it and writes neutral -> OE low.
    bus.attach(0x40, &chip);
    b.start(20'000);
    EXPECT_EQ(oe.level(), 0);
    EXPECT_TRUE(b.outputs_enabled());
    EXPECT_EQ(chip.reg(0x00) & 0x40, 0x40);  // EXTCLK
    // Brown-out: the chip comes back asleep; the check at 1 s sets it up again with OE high,
    // and the next cycle's pulses enable the outputs again.
    chip.power_cycle();
    b.poll_telemetry(2'000'000);
    EXPECT_EQ(oe.level(), 1);
    b.write(neutral, 2'010'000);
    EXPECT_EQ(oe.level(), 0);
    EXPECT_EQ(oe.changes, 3);
  }
  EXPECT_EQ(oe.level(), 1);  // the process let go: outputs off
}

TEST(Pca9685, OutputEnableLineIsReadFromTheConfig) {
  const auto cfg = parse_config(pca_yaml(", output_enable: {chip: gpiochip0, line: 26}"));
  EXPECT_EQ(cfg.pca9685.oe_chip, "gpiochip0");
  EXPECT_EQ(cfg.pca9685.oe_line, 26);
  EXPECT_EQ(parse_config(pca_yaml()).pca9685.oe_line, -1);
  EXPECT_THROW(parse_config(pca_yaml(", output_enable: {line: -1}")), std::exception);
}

TEST(Pca9685, ModelPrescaleOnlyWhileAsleep) {
  i2c::FakeBus bus;
  esc::fake::Pca9685Model m;
  bus.attach(0x40, &m);
  const Bytes wake{0x00, 0x20}, pre{0xFE, 0x79}, sleep{0x00, 0x30};
  bus.write(0x40, wake.data(), 2);
  bus.write(0x40, pre.data(), 2);
  EXPECT_EQ(m.reg(0xFE), 0x1E);  // ignored: awake
  EXPECT_EQ(m.prescale_writes_ignored(), 1);
  bus.write(0x40, sleep.data(), 2);
  bus.write(0x40, pre.data(), 2);
  EXPECT_EQ(m.reg(0xFE), 0x79);
  // Going to sleep while running sets RESTART; writing 1 clears it.
  EXPECT_EQ(m.reg(0x00) & 0x80, 0x80);
  const Bytes restart{0x00, 0xA0};
  bus.write(0x40, wake.data(), 2);
  bus.write(0x40, restart.data(), 2);
  EXPECT_EQ(m.reg(0x00) & 0x80, 0);
  // Without AI, a multi-byte write keeps hitting one register.
  const Bytes no_ai{0x00, 0x00}, burst{0x06, 0x11, 0x22, 0x33};
  bus.write(0x40, no_ai.data(), 2);
  bus.write(0x40, burst.data(), 4);
  EXPECT_EQ(m.reg(0x06), 0x33);
  EXPECT_EQ(m.reg(0x07), 0x00);
  // Oscillator: no pulses until 500 us after waking.
  EXPECT_FALSE(m.oscillator_running(bus.now() + 499));
  EXPECT_TRUE(m.oscillator_running(bus.now() + 500));
}

TEST(Pca9685, NackCountsOnEveryChannelOfTheBoard) {
  Rig r(pca_yaml("", "disarm_on_timeout: false\n"));
  r.run_until(0);
  r.bus.fail(0x40, EREMOTEIO, 4);  // the four channel writes of one cycle
  r.run_until(10'000);
  r.run_until(100'000);
  const auto st = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(st.write_errors, (std::vector<std::int64_t>{1, 1, 1, 1}));
  EXPECT_EQ(st.last_errno, (std::vector<std::int32_t>{EREMOTEIO, EREMOTEIO, EREMOTEIO, EREMOTEIO}));
  EXPECT_EQ(st.backend, "pca9685");
}

TEST(Pca9685, BoardThatAppearsLateIsInitialised) {
  Rig r(pca_yaml("", "missing_esc: degraded\n"));
  r.bus.detach(0x40);
  const auto rep = r.node->start(0);
  EXPECT_FALSE(rep.all_present);
  EXPECT_NE(rep.message.find("no PCA9685 at 0x40 on fake-i2c: ENXIO"), std::string::npos)
      << rep.message;
  r.run_until(500'000);
  r.bus.attach(0x40, r.pca.get());  // powered up late: asleep, default prescale
  r.run_until(1'000'000);           // the once-a-second check initialises it
  EXPECT_FALSE(r.pca->sleeping());
  EXPECT_EQ(r.pca->reg(0xFE), 0x79);
  r.run_until(1'010'000);
  EXPECT_NEAR(r.pca->pulse_us(0, r.bus.now()), 307 * 4.88, 1e-9);
  r.run_until(1'100'000);
  const auto st = r.cap.last<esc_bus_status_t>(channels::kEscStatus);
  EXPECT_EQ(st.present, (std::vector<std::int8_t>{1, 1, 1, 1}));
}

TEST(Pca9685, BoardThatLostPowerIsInitialisedAgain) {
  Rig r(pca_yaml("", "disarm_on_timeout: false\n"));
  r.arm(true);
  r.run_until(200'000);
  r.pca->power_cycle();  // brown-out: asleep, no pulses
  r.run_until(210'000);
  EXPECT_EQ(r.pca->pulse_us(0, r.bus.now()), 0.0);
  r.run_until(1'000'000);
  EXPECT_FALSE(r.pca->sleeping());
  const auto& b = dynamic_cast<const esc::Pca9685Backend&>(r.node->backend());
  EXPECT_EQ(b.reinits(), 1);
  r.run_until(1'010'000);
  EXPECT_NEAR(r.pca->pulse_us(0, r.bus.now()), 307 * 4.88, 1e-9);
}

TEST(Pca9685, ShutdownLeavesEveryChannelAtNeutral) {
  Rig r(seed001());
  r.arm(true);
  r.command({0.9, -0.9, 0.5, -0.5, 1.0, -1.0}, kRov6);
  r.run_until(10'000);
  EXPECT_GT(std::abs(r.pca->pulse_us(1, r.bus.now()) - 1500), 300);
  r.node->shutdown(15'000);
  for (int c : {1, 2, 3, 8, 9, 11}) {
    EXPECT_NEAR(r.pca->pulse_us(c, r.bus.now()), 307 * 4.88, 1e-9) << c;
  }
  const auto o = r.output();
  EXPECT_EQ(o.value, (std::vector<std::int32_t>(6, 1500)));
}

TEST(Pca9685, OpenDrainOutput) {
  Rig r(pca_yaml(", output: open_drain"));
  r.node->start(0);
  EXPECT_EQ(r.pca->reg(0x01), 0x00);
}

}  // namespace
}  // namespace tiller::test
