// The dry-run backend prints the transactions the real backend makes (answered by the device
// models): every distinct write once in "changes" mode, everything in "every_cycle" mode.
#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "esc_rig.hpp"

namespace tiller::test {
namespace {

std::string read_all(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  return s;
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

struct DryRig {
  std::FILE* out = std::tmpfile();
  std::unique_ptr<EscNode> node;
  Capture cap;
  explicit DryRig(esc::EscConfig cfg) {
    node = std::make_unique<EscNode>(cfg.node, esc::make_backend(cfg, nullptr, out));
    node->attach(&cap);
  }
  ~DryRig() { std::fclose(out); }
  void command(const std::vector<std::string>& names, const std::vector<double>& u, TimeUs t) {
    thruster_command_t m{};
    m.utime = t;
    m.armed = true;
    m.arm_allowed = true;
    m.n_thrusters = static_cast<std::int32_t>(u.size());
    m.names = names;
    m.command = u;
    const Event e = encode(channels::kThrusterCommand, t, m);
    node->deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), t);
  }
  void arm(TimeUs t) {
    arm_request_t a{};
    a.arm = true;
    a.source = "test";
    const Event e = encode(channels::kArmRequest, t, a);
    node->deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), t);
  }
};

esc::EscConfig preset(const std::string& name) {
  return esc::load_esc_config_file(std::string(TILLER_SOURCE_DIR) + "/config/esc/" + name);
}

TEST(DryRun, Seed000PrintsTheI2cBytesOncePerChange) {
  DryRig r(preset("seed000_dry_run.yaml"));
  const auto rep = r.node->start(0);
  EXPECT_TRUE(rep.all_present) << rep.message;
  for (TimeUs t = 0; t <= 100'000; t += 10'000) r.node->tick(t);
  r.arm(100'000);
  r.command({"t1", "t2", "t3", "t4"}, {0.5, -1.0, 0.0, 0.0}, 100'000);
  for (TimeUs t = 110'000; t <= 200'000; t += 10'000) r.node->tick(t);
  r.node->shutdown(205'000);
  const std::string s = read_all(r.out);
  // Start: neutral once per ESC (then unchanged for 11 cycles: not printed again).
  EXPECT_EQ(count(s, "0x29 write 00 00 00"), 2u) << s;  // start, shutdown
  // The command goes on the bus at the instant it arrives (armed, write_on_command).
  EXPECT_NE(s.find("dry-run 0.100000 s 0x29 write 00 40 00"), std::string::npos) << s;
  EXPECT_NE(s.find("dry-run 0.100000 s 0x2a write 00 80 01"), std::string::npos) << s;
  EXPECT_EQ(count(s, "0x29 write 00 40 00"), 1u) << s;
  EXPECT_NE(s.find("dry-run 0.205000 s 0x2a write 00 00 00"), std::string::npos) << s;
  EXPECT_EQ(r.node->last_output().backend, "dry_run");
}

TEST(DryRun, EveryCycleModePrintsReadsToo) {
  auto cfg = preset("seed000_dry_run.yaml");
  cfg.dry_run.every_cycle = true;
  DryRig r(cfg);
  for (TimeUs t = 0; t <= 30'000; t += 10'000) r.node->tick(t);
  const std::string s = read_all(r.out);
  EXPECT_EQ(count(s, "0x2c write 00 00 00"), 5u) << s;    // start + 4 cycles
  EXPECT_EQ(count(s, "write-read 02 ->"), 4u + 4u) << s;  // start probes + 1 per cycle
  EXPECT_NE(s.find(" ab\n"), std::string::npos) << s;     // the model's 0xAB
}

TEST(DryRun, Seed001PrintsThePca9685StartUp) {
  DryRig r(preset("seed001_dry_run.yaml"));
  EXPECT_TRUE(r.node->start(0).all_present);
  const std::string s = read_all(r.out);
  const auto a = s.find("0x40 write 00 30");
  const auto b = s.find("0x40 write fe 79");
  const auto c = s.find("wait 500 us");
  const auto d = s.find("0x40 write 0a 00 00 33 01");  // channel 1 (F) neutral
  ASSERT_NE(a, std::string::npos) << s;
  ASSERT_NE(d, std::string::npos) << s;
  EXPECT_LT(a, b);
  EXPECT_LT(b, c);
  EXPECT_LT(c, d);
}

TEST(DryRun, Pca9685SteadyCommandsPrintNothingMore) {
  // "changes" mode keeps one slot per (address, register): after start-up and one write of each
  // channel, 10 cycles of unchanged neutral print nothing, and one changed channel prints one
  // line (every PCA9685 channel has its own LEDn register, six channels on one address).
  DryRig r(preset("seed001_dry_run.yaml"));
  r.node->tick(0);
  r.node->tick(10'000);
  const std::size_t after_start = read_all(r.out).size();
  for (int k = 2; k < 12; ++k) r.node->tick(k * 10'000);
  EXPECT_EQ(read_all(r.out).size(), after_start) << read_all(r.out).substr(after_start);
  r.arm(115'000);
  r.command({"F", "LF", "RF", "B", "LB", "RB"}, {0.5, 0, 0, 0, 0, 0}, 116'000);
  r.node->tick(120'000);
  const std::string more = read_all(r.out).substr(after_start);
  EXPECT_EQ(count(more, "0x40 write"), 1u) << more;
}

TEST(DryRun, UnpluggedRehearsesAMissingEsc) {
  auto cfg = preset("seed000_dry_run.yaml");
  cfg.dry_run.unplugged = {0x2b};
  DryRig r(cfg);
  const auto rep = r.node->start(0);
  EXPECT_FALSE(rep.all_present);
  EXPECT_NE(rep.message.find("ESC t3: nothing at 0x2b on dry-run: ENXIO"), std::string::npos)
      << rep.message;
  const std::string s = read_all(r.out);
  EXPECT_NE(s.find("0x2b write 00 00 00 FAILED ENXIO"), std::string::npos) << s;
}

}  // namespace
}  // namespace tiller::test
