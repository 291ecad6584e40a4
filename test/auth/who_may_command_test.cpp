// Who may command (docs/safety.md), through the real tiller-esc process over LCM in the private
// network namespace of tools/netns-run, with its dry-run bus (every bus write on its stdout).
// The test plays the vehicle's legitimate senders with the vehicle key (a "mixer" sending
// neutral commands, a "teleop" arming) and an attacker:
//   * a foreign unsigned TILLER_THRUSTER_COMMAND of 0.8 never reaches the ESC bus (issue 12,
//     finding 6), nor a signed one from a sender other than the mixer;
//   * a process with a wrong key (a real tiller-mission, and a "mixer" with another key) is
//     refused and counted, and the ESC stays disarmed and neutral;
//   * a captured valid arm request replayed is refused (replay, then window after a restart);
//   * a captured non-neutral thruster command replayed is refused; the outputs stay neutral.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include "../e2e/e2e_util.hpp"
#include "auth/key.hpp"
#include "auth/trailer.hpp"
#include "runtime/channels.hpp"

namespace tiller {
namespace {

namespace fs = std::filesystem;
using e2e::kUrl;
using e2e::realtime_us;
const std::string kSrc = TILLER_SOURCE_DIR;
const std::string kEsc = std::string(TILLER_BIN_DIR) + "/tiller-esc";
const std::string kHeartbeat = "TILLER_HEARTBEAT_ESC";

struct Dir {
  fs::path p = fs::temp_directory_path() / ("tiller_who_" + std::to_string(::getpid()));
  Dir() { fs::create_directories(p); }
  ~Dir() { fs::remove_all(p); }
  std::string key(const std::string& name) const {
    const std::string f = (p / name).string();
    if (!fs::exists(f)) auth::write_key_file(f, auth::generate_key(), false);
    return f;
  }
  std::string file(const std::string& name) const { return (p / name).string(); }
};

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Publishes messages signed as one sender (or unsigned without a key), and raw packets.
struct Sender {
  lcm::LCM& l;
  std::optional<auth::Signer> signer;
  Sender(lcm::LCM& lc, const std::string& key_file, const std::string& name) : l(lc) {
    if (!key_file.empty()) signer.emplace(auth::load_key_file(key_file), name);
  }
  template <class Msg>
  void publish(const std::string& channel, const Msg& m) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    const int n = static_cast<int>(buf.size());
    if (signer) {
      buf.resize(buf.size() + auth::kTrailerSize);
      signer->sign(channel, buf.data(), n, realtime_us(), buf.data() + n);
    }
    l.publish(channel, buf.data(), static_cast<unsigned>(buf.size()));
  }
};

thruster_command_t command(double v, bool armed) {
  thruster_command_t c{};
  c.utime = realtime_us();
  c.armed = armed;
  c.n_thrusters = 4;
  c.names = {"t1", "t2", "t3", "t4"};
  c.command = {v, v, v, v};
  // As the mixer's intent gate says it: a neutral demand lets tiller-esc grant an arm request.
  c.gate = armed ? thruster_command_t::GATE_ACTIVE : thruster_command_t::GATE_DISARMED;
  c.arm_allowed = v == 0.0;
  return c;
}

// An arm request carries the boot nonce of tiller-esc's latest arm state (0: none heard).
arm_request_t arm_request(bool arm, std::int64_t nonce = 0, const std::string& station = "") {
  arm_request_t a{};
  a.utime = realtime_us();
  a.arm = arm;
  a.source = "who_may_command_test";
  a.boot_nonce = nonce;
  a.station = station;
  return a;
}

// What the test hears: the ESC's outputs, arm state and heartbeat counters, and raw packets.
struct Ear {
  std::vector<esc_output_t> outputs;
  arm_state_t arm{};
  bool have_arm = false;
  heartbeat_t hb{};
  int heartbeats = 0;
  std::vector<std::vector<std::uint8_t>> arm_packets, command_packets;
  void on_output(const lcm::ReceiveBuffer*, const std::string&, const esc_output_t* m) {
    outputs.push_back(*m);
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_state_t* m) {
    arm = *m;
    have_arm = true;
  }
  void on_hb(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) {
    hb = *m;
    ++heartbeats;
  }
  void on_raw(const lcm::ReceiveBuffer* rb, const std::string& ch) {
    const auto* p = static_cast<const std::uint8_t*>(rb->data);
    auto& into = ch == channels::kArmRequest ? arm_packets : command_packets;
    into.emplace_back(p, p + rb->data_size);
  }
  std::int64_t counter(const std::string& name) const {
    for (int i = 0; i < hb.n_counters; ++i)
      if (hb.counter_names[static_cast<std::size_t>(i)] == name)
        return hb.counter_values[static_cast<std::size_t>(i)];
    return -1;
  }
};

struct Rig {
  Dir dir;
  lcm::LCM l{kUrl};
  Ear ear;
  Rig() {
    l.subscribe(channels::kEscOutput, &Ear::on_output, &ear);
    l.subscribe(channels::kArmState, &Ear::on_arm, &ear);
    l.subscribe(kHeartbeat, &Ear::on_hb, &ear);
    l.subscribe(channels::kArmRequest, &Ear::on_raw, &ear);
    l.subscribe(channels::kThrusterCommand, &Ear::on_raw, &ear);
  }
  // tiller-esc on the dry-run bus, signing with `key`, refusing unsigned input.
  std::unique_ptr<e2e::Proc> esc(const std::string& key, const std::string& out,
                                 const std::string& window_s = "1") {
    return std::make_unique<e2e::Proc>(
        kEsc,
        std::vector<std::string>{"--config", kSrc + "/config/esc/seed000_dry_run.yaml", "--lcm-url",
                                 kUrl, "--key-file", key, "--require-signed", "--auth-window-s",
                                 window_s},
        false, dir.file(out));
  }
  // Waits for tiller-esc's first arm state (its boot nonce) and heartbeat.
  bool up(const std::function<void()>& each) {
    return pump([&] { return ear.heartbeats > 0 && ear.have_arm; }, 10.0, each);
  }
  // Pumps LCM until pred() or `seconds`; each() runs every 10 ms (a sender's rate).
  bool pump(const std::function<bool()>& pred, double seconds,
            const std::function<void()>& each = {}) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      if (pred()) return true;
      if (each) each();
      l.handleTimeout(10);
    }
    return pred();
  }
  // Waits for a heartbeat stamped after now (so it reflects what came before).
  bool fresh_heartbeat(const std::function<void()>& each = {}) {
    const std::int64_t t = realtime_us();
    return pump([&] { return ear.heartbeats > 0 && ear.hb.utime > t; }, 4.0, each);
  }
  // The ESC handles one message per loop turn, between ticks: a heartbeat may come before a
  // burst is worked through. Waits (a deadline, not a timing claim) for `name` to reach `n`,
  // then for one more heartbeat, so a count beyond n would show too.
  std::int64_t counter_after(const std::string& name, std::int64_t n,
                             const std::function<void()>& each = {}) {
    pump([&] { return ear.counter(name) >= n; }, 8.0, each);
    fresh_heartbeat(each);
    return ear.counter(name);
  }
};

bool all_neutral(const esc_output_t& o) {
  for (std::int32_t v : o.value)
    if (v != 0) return false;
  return true;
}

// Every ESC write on the dry-run bus was neutral (00 00 00 on the four BlueESCs).
void expect_bus_neutral(const std::string& out) {
  std::istringstream in(out);
  std::string line;
  int writes = 0;
  while (std::getline(in, line)) {
    const auto w = line.find(" write ");
    if (w == std::string::npos) continue;
    ++writes;
    EXPECT_EQ(line.substr(w, 16), " write 00 00 00") << line;
  }
  EXPECT_GT(writes, 0) << out;
}

TEST(WhoMayCommand, ForeignThrusterCommandsNeverReachTheBus) {
  Rig r;
  ASSERT_TRUE(r.l.good()) << "LCM not available: is this test under tools/netns-run?";
  const std::string key = r.dir.key("vehicle.key");
  auto esc = r.esc(key, "esc1.out");
  Sender mixer(r.l, key, "mixer"), teleop(r.l, key, "teleop");
  Sender foreign(r.l, "", "");         // no key: unsigned
  Sender insider(r.l, key, "teleop");  // the vehicle key, but not the mixer's identity
  auto neutral = [&] { mixer.publish(channels::kThrusterCommand, command(0, true)); };
  ASSERT_TRUE(r.up(neutral)) << slurp(r.dir.file("esc1.out"));
  teleop.publish(channels::kArmRequest, arm_request(true, r.ear.arm.boot_nonce));
  ASSERT_TRUE(r.pump([&] { return r.ear.have_arm && r.ear.arm.armed; }, 5.0, neutral))
      << "the legitimate arm request was not accepted: " << slurp(r.dir.file("esc1.out"));
  // Foreign commands of 0.8 among the mixer's neutral ones, armed all along, until the ESC has
  // refused 50 of each (UDP may drop some on a loaded machine: every one that arrived counts).
  int sent = 0;
  r.pump(
      [&] {
        return r.ear.counter("rejected.auth.unsigned") >= 50 &&
               r.ear.counter("rejected.auth.sender") >= 50;
      },
      30.0,
      [&] {
        foreign.publish(channels::kThrusterCommand, command(0.8, true));
        insider.publish(channels::kThrusterCommand, command(0.8, true));
        neutral();
        ++sent;
        e2e::sleep_ms(5);  // a mixer's rate, not a burst
      });
  ASSERT_TRUE(r.fresh_heartbeat(neutral));
  EXPECT_GE(r.ear.counter("rejected.auth.unsigned"), 50);
  EXPECT_LE(r.ear.counter("rejected.auth.unsigned"), sent);
  EXPECT_GE(r.ear.counter("rejected.auth.sender"), 50);
  EXPECT_LE(r.ear.counter("rejected.auth.sender"), sent);
  EXPECT_TRUE(r.ear.arm.armed);
  ASSERT_FALSE(r.ear.outputs.empty());
  for (const auto& o : r.ear.outputs) ASSERT_TRUE(all_neutral(o)) << "an output left neutral";
  esc->stop();
  const std::string out = slurp(r.dir.file("esc1.out"));
  expect_bus_neutral(out);
  EXPECT_NE(out.find("refused a message on TILLER_THRUSTER_COMMAND: it is not signed, and "
                     "require_signed is on"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("from 'teleop': this node accepts it only from its declared senders"),
            std::string::npos)
      << out;
}

TEST(WhoMayCommand, AProcessWithAWrongKeyIsRefused) {
  Rig r;
  ASSERT_TRUE(r.l.good());
  const std::string key = r.dir.key("vehicle.key");
  const std::string other = r.dir.key("other.key");
  auto esc = r.esc(key, "esc2.out");
  Sender wrong_mixer(r.l, other, "mixer"), wrong_teleop(r.l, other, "teleop");
  auto attack = [&] {
    wrong_mixer.publish(channels::kThrusterCommand, command(0.8, true));
    wrong_teleop.publish(channels::kArmRequest, arm_request(true));
  };
  ASSERT_TRUE(r.pump([&] { return r.ear.heartbeats > 0; }, 10.0, attack));
  // A real process with the wrong key: tiller-mission publishes its path, mode and arm request.
  {
    e2e::Proc mission(std::string(TILLER_BIN_DIR) + "/tiller-mission",
                      {"--mission", kSrc + "/config/missions/default.yaml", "--repeat-s", "0",
                       "--lcm-url", kUrl, "--key-file", other},
                      false, r.dir.file("mission.out"));
    for (int i = 0; i < 1000 && mission.running(); ++i) r.l.handleTimeout(10);
    EXPECT_EQ(mission.stop(), 0) << slurp(r.dir.file("mission.out"));  // it published and left
  }
  for (int i = 0; i < 30; ++i) {
    attack();
    r.l.handleTimeout(10);
  }
  EXPECT_GE(r.counter_after("rejected.auth.wrong_key", 2 * 30 + 1),
            2 * 30 + 1);  // + the mission's request (the heartbeat's attacks add more)
  EXPECT_FALSE(r.ear.have_arm && r.ear.arm.armed);
  for (const auto& o : r.ear.outputs) ASSERT_TRUE(all_neutral(o));
  esc->stop();
  const std::string out = slurp(r.dir.file("esc2.out"));
  expect_bus_neutral(out);
  EXPECT_NE(out.find("it is signed with another key than this process's"), std::string::npos)
      << out;
}

TEST(WhoMayCommand, ReplayedArmRequestIsRefused) {
  Rig r;
  ASSERT_TRUE(r.l.good());
  const std::string key = r.dir.key("vehicle.key");
  auto esc = r.esc(key, "esc3.out");
  Sender mixer(r.l, key, "mixer"), teleop(r.l, key, "teleop");
  auto neutral = [&] { mixer.publish(channels::kThrusterCommand, command(0, false)); };
  ASSERT_TRUE(r.up(neutral));
  teleop.publish(channels::kArmRequest, arm_request(true, r.ear.arm.boot_nonce));
  ASSERT_TRUE(r.pump([&] { return r.ear.have_arm && r.ear.arm.armed; }, 5.0, neutral));
  ASSERT_EQ(r.ear.arm_packets.size(), 1u);
  const auto captured = r.ear.arm_packets.front();  // as it was on the wire
  ASSERT_TRUE(auth::has_trailer(captured.data(), static_cast<int>(captured.size())));
  teleop.publish(channels::kArmRequest, arm_request(false));
  ASSERT_TRUE(r.pump([&] { return !r.ear.arm.armed; }, 5.0, neutral));
  // The capture, replayed to the running ESC: an old stamp of a known stream.
  for (int i = 0; i < 5; ++i) r.l.publish(channels::kArmRequest, captured.data(), captured.size());
  EXPECT_EQ(r.counter_after("rejected.auth.replay", 5, neutral), 5);
  EXPECT_FALSE(r.ear.arm.armed);
  // A restarted ESC knows no stream: the capture is refused as older than the window (1 s).
  esc->stop();
  r.ear.heartbeats = 0;
  esc = r.esc(key, "esc3b.out");
  ASSERT_TRUE(r.pump([&] { return r.ear.heartbeats > 0; }, 10.0, neutral));
  const TimeUs stamp = auth::read_trailer(captured.data() + captured.size() - 48).time_us;
  r.pump([&] { return realtime_us() - stamp > 1'200'000; }, 5.0, neutral);  // past the window
  for (int i = 0; i < 5; ++i) r.l.publish(channels::kArmRequest, captured.data(), captured.size());
  EXPECT_EQ(r.counter_after("rejected.auth.window", 5, neutral), 5);
  EXPECT_FALSE(r.ear.arm.armed);
  for (const auto& o : r.ear.outputs) EXPECT_TRUE(all_neutral(o));
  esc->stop();
  expect_bus_neutral(slurp(r.dir.file("esc3b.out")));
}

TEST(WhoMayCommand, ReplayedThrusterCommandIsRefused) {
  Rig r;
  ASSERT_TRUE(r.l.good());
  const std::string key = r.dir.key("vehicle.key");
  auto esc = r.esc(key, "esc4.out");
  Sender mixer(r.l, key, "mixer"), teleop(r.l, key, "teleop");
  double v = 0;
  auto send = [&] { mixer.publish(channels::kThrusterCommand, command(v, true)); };
  ASSERT_TRUE(r.up(send));
  teleop.publish(channels::kArmRequest, arm_request(true, r.ear.arm.boot_nonce));
  ASSERT_TRUE(r.pump([&] { return r.ear.have_arm && r.ear.arm.armed; }, 5.0, send));
  // The mixer commands 0.5 for a moment: the ESC obeys (16384 = 0.5 of full throttle).
  v = 0.5;
  r.ear.command_packets.clear();
  ASSERT_TRUE(r.pump(
      [&] { return !r.ear.outputs.empty() && r.ear.outputs.back().value[0] == 16384; }, 5.0, send));
  ASSERT_FALSE(r.ear.command_packets.empty());
  const auto captured = r.ear.command_packets.back();
  // Back to neutral; from the first neutral output on, every output must stay neutral.
  v = 0;
  ASSERT_TRUE(r.pump([&] { return all_neutral(r.ear.outputs.back()); }, 5.0, send));
  const std::size_t from = r.ear.outputs.size();
  int replays = 0;
  r.pump([&] { return r.ear.counter("rejected.auth.replay") >= 40; }, 30.0,
         [&] {
           send();
           r.l.publish(channels::kThrusterCommand, captured.data(), captured.size());
           ++replays;
           e2e::sleep_ms(5);
         });
  ASSERT_TRUE(r.fresh_heartbeat(send));
  EXPECT_GE(r.ear.counter("rejected.auth.replay"), 40);
  EXPECT_LE(r.ear.counter("rejected.auth.replay"), replays);
  EXPECT_TRUE(r.ear.arm.armed);
  ASSERT_GT(r.ear.outputs.size(), from);
  for (std::size_t i = from; i < r.ear.outputs.size(); ++i)
    ASSERT_TRUE(all_neutral(r.ear.outputs[i])) << "output " << i << " left neutral";
}

// Issue 30, scenario 2: a signed arm request captured live and replayed into a restarted ESC at
// once, well inside the signing window (here 10 s, so the window cannot be what stops it; a
// wall-clock step changes nothing either: the nonce is not a time). Before the boot nonce the
// restarted ESC (which knows no stream yet) re-armed; now it refuses and counts each replay.
TEST(WhoMayCommand, ArmReplayedIntoARestartedEscIsRefused) {
  Rig r;
  ASSERT_TRUE(r.l.good());
  const std::string key = r.dir.key("vehicle.key");
  auto esc = r.esc(key, "esc5.out", "10");
  Sender mixer(r.l, key, "mixer"), teleop(r.l, key, "teleop");
  auto neutral = [&] { mixer.publish(channels::kThrusterCommand, command(0, false)); };
  ASSERT_TRUE(r.up(neutral));
  const std::int64_t first_nonce = r.ear.arm.boot_nonce;
  EXPECT_NE(first_nonce, 0);
  teleop.publish(channels::kArmRequest, arm_request(true, first_nonce));
  ASSERT_TRUE(r.pump([&] { return r.ear.arm.armed; }, 5.0, neutral));
  ASSERT_EQ(r.ear.arm_packets.size(), 1u);
  const auto captured = r.ear.arm_packets.front();
  esc->stop();  // the vehicle's ESC process restarts
  r.ear.heartbeats = 0;
  r.ear.have_arm = false;
  esc = r.esc(key, "esc5b.out", "10");
  ASSERT_TRUE(r.up(neutral));
  EXPECT_NE(r.ear.arm.boot_nonce, first_nonce) << "a new start draws a new nonce";
  const TimeUs stamp = auth::read_trailer(captured.data() + captured.size() - 48).time_us;
  const std::size_t from = r.ear.outputs.size();
  int replays = 0;
  // The first replay passes the signature checks (the new ESC knows no stream) and meets the
  // nonce; the later copies are stopped earlier, as replays of that stream.
  r.pump(
      [&] {
        return r.ear.counter("rejected.arm_request.boot_nonce") >= 1 &&
               r.ear.counter("rejected.auth.replay") >= 10;
      },
      8.0,
      [&] {
        neutral();
        r.l.publish(channels::kArmRequest, captured.data(), captured.size());
        ++replays;
        e2e::sleep_ms(20);
      });
  EXPECT_LT(realtime_us() - stamp, 10'000'000) << "the replays were inside the signing window";
  ASSERT_TRUE(r.fresh_heartbeat(neutral));
  EXPECT_EQ(r.ear.counter("rejected.arm_request.boot_nonce"), 1);
  EXPECT_GE(r.ear.counter("rejected.auth.replay"), 10);
  EXPECT_LE(r.ear.counter("rejected.auth.replay") + 1, replays);
  EXPECT_FALSE(r.ear.arm.armed);
  EXPECT_NE(r.ear.arm.reason.find("boot nonce differs"), std::string::npos) << r.ear.arm.reason;
  int off = 0;
  for (std::size_t i = from; i < r.ear.outputs.size(); ++i) off += !all_neutral(r.ear.outputs[i]);
  EXPECT_EQ(off, 0) << "outputs off neutral after the restart";
  std::printf("replayed arm into a restarted ESC: %d replays, %d of %zu outputs off neutral\n",
              replays, off, r.ear.outputs.size() - from);
  esc->stop();
  expect_bus_neutral(slurp(r.dir.file("esc5b.out")));
}

// Issue 30, scenario 3 at the ESC: station A arms; station B (same key) is refused and told who
// holds control; B's takeover is a new session that names B, and A's disarm still stops it.
TEST(WhoMayCommand, OneStationInControlAndATakeoverIsSeen) {
  Rig r;
  ASSERT_TRUE(r.l.good());
  const std::string key = r.dir.key("vehicle.key");
  auto esc = r.esc(key, "esc6.out");
  Sender mixer(r.l, key, "mixer"), a(r.l, key, "teleop"), b(r.l, key, "teleop_b");
  auto neutral = [&] { mixer.publish(channels::kThrusterCommand, command(0, false)); };
  ASSERT_TRUE(r.up(neutral));
  const std::int64_t nonce = r.ear.arm.boot_nonce;
  a.publish(channels::kArmRequest, arm_request(true, nonce, "A"));
  ASSERT_TRUE(r.pump([&] { return r.ear.arm.armed && r.ear.arm.controller == "A"; }, 5.0, neutral));
  const std::int64_t session = r.ear.arm.session;
  b.publish(channels::kArmRequest, arm_request(true, nonce, "B"));
  ASSERT_TRUE(r.pump(
      [&] { return r.ear.arm.reason.find("another station in control: A") != std::string::npos; },
      5.0, neutral))
      << r.ear.arm.reason;
  EXPECT_EQ(r.ear.arm.controller, "A");
  EXPECT_EQ(r.ear.arm.session, session);
  EXPECT_EQ(r.counter_after("rejected.arm_request.station", 1, neutral), 1);
  arm_request_t take = arm_request(true, nonce, "B");
  take.takeover = true;
  b.publish(channels::kArmRequest, take);
  ASSERT_TRUE(r.pump([&] { return r.ear.arm.controller == "B"; }, 5.0, neutral));
  EXPECT_EQ(r.ear.arm.reason, "control taken by B from A");
  EXPECT_EQ(r.ear.arm.session, session + 1) << "a takeover is a new session";
  EXPECT_TRUE(r.ear.arm.armed);
  EXPECT_EQ(r.counter_after("arm.takeovers", 1, neutral), 1);
  a.publish(channels::kArmRequest, arm_request(false, 0, "A"));  // any station may stop it
  ASSERT_TRUE(r.pump([&] { return !r.ear.arm.armed; }, 5.0, neutral));
  EXPECT_EQ(r.ear.arm.controller, "");
}

}  // namespace
}  // namespace tiller
