// tiller-teleop as a real process over LCM in a private network namespace, its joystick a FIFO:
// stick events reach TILLER_MANUAL_DEMAND,
// the arm button gives one TILLER_ARM_REQUEST, closing the FIFO's writer gives a neutral,
// invalid demand and a DEGRADED heartbeat, reopening it resumes only after centring, and
// SIGTERM ends the process with status 0. A regular file as the device: appended records are
// events, removing the file is unplugging.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <functional>
#include <vector>

#include <tiller/arm_request_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/joystick_state_t.hpp>
#include <tiller/manual_demand_t.hpp>

#include "../e2e/e2e_util.hpp"

namespace tiller::e2e {
namespace {

struct Rx {
  void on_demand(const lcm::ReceiveBuffer*, const std::string&, const manual_demand_t* m) {
    demand = *m;
    demand_t = realtime_us();
    ++n_demand;
  }
  void on_arm(const lcm::ReceiveBuffer*, const std::string&, const arm_request_t* m) {
    arm = *m;
    ++n_arm;
  }
  void on_js(const lcm::ReceiveBuffer*, const std::string&, const joystick_state_t* m) { js = *m; }
  void on_hb(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) { hb = *m; }
  manual_demand_t demand{};
  std::int64_t demand_t = 0;
  int n_demand = 0, n_arm = 0;
  arm_request_t arm{};
  joystick_state_t js{};
  heartbeat_t hb{};
};

bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds) {
  const std::int64_t end = realtime_us() + static_cast<std::int64_t>(seconds * 1e6);
  while (realtime_us() < end) {
    if (pred()) return true;
    l.handleTimeout(5);
  }
  return pred();
}

TEST(TeleopLive, FifoStickThroughTheRealProcess) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "LCM not available: run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_MANUAL_DEMAND", &Rx::on_demand, &rx);
  l.subscribe("TILLER_ARM_REQUEST", &Rx::on_arm, &rx);
  l.subscribe("TILLER_JOYSTICK", &Rx::on_js, &rx);
  l.subscribe("TILLER_HEARTBEAT_TELEOP", &Rx::on_hb, &rx);
  FifoStick stick("/tmp/tiller_teleop_live_js_" + std::to_string(getpid()));
  Proc teleop(
      std::string(TILLER_BIN_DIR) + "/tiller-teleop",
      {"--config", std::string(TILLER_SOURCE_DIR) + "/config/teleop/extreme3dpro_seed000.yaml",
       "--device", stick.path(), "--lcm-url", kUrl});

  ASSERT_TRUE(pump_until(
      l, [&] { return rx.hb.utime != 0 && rx.n_demand > 3; }, 5.0));
  EXPECT_EQ(rx.hb.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(rx.hb.status.find("joystick absent"), std::string::npos) << rx.hb.status;
  EXPECT_FALSE(rx.demand.valid);

  stick.plug();
  stick.init({0, 0, 0, 32767, 0, 0});
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.valid && rx.js.connected; }, 3.0));
  EXPECT_EQ(rx.js.n_axes, 6);
  EXPECT_EQ(rx.js.n_buttons, 12);

  stick.axis(1, -32767);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.demand[0] == 1.0; }, 2.0));
  EXPECT_EQ(rx.demand.demand[1], 0.0);
  stick.axis(1, 0);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.demand[0] == 0.0; }, 2.0));

  stick.button(6, true);
  sleep_ms(100);
  stick.button(6, false);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.n_arm == 1; }, 2.0));
  EXPECT_TRUE(rx.arm.arm);
  EXPECT_EQ(rx.arm.source, "teleop");
  pump_until(
      l, [] { return false; }, 0.2);
  EXPECT_EQ(rx.n_arm, 1);

  // Malformed records (an unknown type, an axis number past 63) are dropped and counted in the
  // heartbeat; the stick stays valid and neutral.
  stick.write(
      {JsEvent{0, 0, 0x04, 0}, JsEvent{0, 1000, kJsEventAxis, 70}, JsEvent{0, 0, kJsEventAxis, 1}});
  auto bad = [&] {
    for (std::size_t i = 0; i < rx.hb.counter_names.size(); ++i)
      if (rx.hb.counter_names[i] == "rejected.js_event.bad") return rx.hb.counter_values[i];
    return std::int64_t{-1};
  };
  ASSERT_TRUE(pump_until(
      l, [&] { return bad() == 2; }, 2.5))
      << bad();
  EXPECT_TRUE(rx.demand.valid);
  EXPECT_EQ(rx.demand.demand[0], 0.0);

  // Pull the plug while held forward: a neutral invalid demand follows (not waiting for a tick).
  stick.axis(1, -32767);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.demand[0] == 1.0; }, 2.0));
  stick.unplug();
  ASSERT_TRUE(pump_until(
      l, [&] { return !rx.demand.valid; }, 2.0));
  EXPECT_EQ(rx.demand.demand[0], 0.0);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.hb.state == heartbeat_t::STATE_DEGRADED && !rx.js.connected; }, 2.5));

  // Plug back with the stick held: stays invalid until centred.
  stick.plug();
  stick.init({0, -32767, 0, 32767, 0, 0});
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.js.connected; }, 3.0));
  pump_until(
      l, [] { return false; }, 0.3);
  EXPECT_FALSE(rx.demand.valid);
  EXPECT_EQ(rx.demand.demand[0], 0.0);
  stick.axis(1, 0);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.valid; }, 2.0));
  stick.axis(1, -32767);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.demand[0] == 1.0; }, 2.0));
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.hb.state == heartbeat_t::STATE_OK; }, 2.5))
      << rx.hb.status;

  EXPECT_TRUE(teleop.running());
  const int status = teleop.stop();
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST(TeleopLive, RegularFileStickRemovedIsUnplug) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "LCM not available: run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_MANUAL_DEMAND", &Rx::on_demand, &rx);
  l.subscribe("TILLER_HEARTBEAT_TELEOP", &Rx::on_hb, &rx);
  const std::string path = "/tmp/tiller_teleop_live_file_" + std::to_string(getpid());
  const auto rec = [] {
    std::FILE* f = std::fopen(TILLER_SOURCE_DIR "/test/data/joystick/e3dp_positions.js", "rb");
    std::vector<unsigned char> b(18 * 8);
    const std::size_t n = f ? std::fread(b.data(), 1, b.size(), f) : 0;
    if (f) std::fclose(f);
    b.resize(n);
    return b;
  }();
  ASSERT_EQ(rec.size(), 18u * 8);
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    std::fwrite(rec.data(), 1, rec.size(), f);  // the INIT block: plugged in, centred
    std::fclose(f);
  }
  Proc teleop(
      std::string(TILLER_BIN_DIR) + "/tiller-teleop",
      {"--config", std::string(TILLER_SOURCE_DIR) + "/config/teleop/extreme3dpro_seed000.yaml",
       "--device", path, "--lcm-url", kUrl});
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.valid; }, 5.0));
  // Appended records are new events (inotify), handled at once.
  {
    std::FILE* f = std::fopen(path.c_str(), "ab");
    JsEvent e{0, -32767, kJsEventAxis, 1};
    std::fwrite(&e, sizeof e, 1, f);
    std::fclose(f);
  }
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.demand.demand[0] == 1.0; }, 2.0));
  // Removing the file is pulling the plug.
  ::unlink(path.c_str());
  ASSERT_TRUE(pump_until(
      l, [&] { return !rx.demand.valid; }, 2.0));
  EXPECT_EQ(rx.demand.demand[0], 0.0);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.hb.status.find("joystick absent") != std::string::npos; }, 2.5))
      << rx.hb.status;
  EXPECT_TRUE(teleop.running());
}

}  // namespace
}  // namespace tiller::e2e
