// Live executor over real udpm LCM between two processes, inside the private network namespace
// that tools/netns-run makes for this test: messages flow both ways, a malformed packet on a
// subscribed channel is dropped and counted (seen in the peer's heartbeat), the peer keeps
// running and answering, and SIGTERM ends it cleanly with status 0.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <functional>

#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/wrench_t.hpp>

#include "runtime/live.hpp"

namespace tiller {
namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

class Listener {
 public:
  void on_wrench(const lcm::ReceiveBuffer*, const std::string&, const wrench_t* m) {
    ++wrenches;
    last_wrench = *m;
  }
  void on_heartbeat(const lcm::ReceiveBuffer*, const std::string&, const heartbeat_t* m) {
    ++heartbeats;
    last_heartbeat = *m;
  }
  int wrenches = 0, heartbeats = 0;
  wrench_t last_wrench{};
  heartbeat_t last_heartbeat{};
};

// Handles LCM until pred() or the deadline.
bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    l.handleTimeout(20);
  }
  return pred();
}

TEST(Live, TwoProcessesExchangeAndMalformedPacketIsCounted) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "LCM not available: is this test running under tools/netns-run?";
  Listener rx;
  l.subscribe("TILLER_WRENCH_VELOCITY", &Listener::on_wrench, &rx);
  l.subscribe("TILLER_HEARTBEAT_TOY_CONTROLLER", &Listener::on_heartbeat, &rx);

  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl(TILLER_TEST_BIN_DIR "/runtime_live_peer", "runtime_live_peer", kUrl, nullptr);
    _exit(127);
  }

  // The peer ticks at 50 Hz and publishes a wrench each tick.
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.wrenches >= 5; }, 5.0))
      << "no wrench from the peer";

  // Odometry changes what it publishes: x = 0.75 -> tau[0] = 2 (1 - 0.75) + 0.3 * integral.
  odometry_t o{};
  o.position[0] = 0.75;
  l.publish("TILLER_ODOMETRY", &o);
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_wrench.tau[5] > 0.0 && rx.last_wrench.tau[5] < 0.5; }, 3.0))
      << "the peer never reported receiving odometry";

  // A malformed packet on a subscribed channel.
  const std::uint8_t junk[7] = {0xde, 0xad, 0xbe, 0xef, 1, 2, 3};
  l.publish("TILLER_ODOMETRY", junk, sizeof junk);
  // A non-finite value.
  odometry_t bad{};
  bad.velocity[0] = std::numeric_limits<double>::infinity();
  l.publish("TILLER_ODOMETRY", &bad);

  ASSERT_TRUE(pump_until(
      l, [&] { return rx.last_heartbeat.rejected >= 2; }, 4.0))
      << "the peer's heartbeat never counted the bad packets";
  EXPECT_EQ(rx.last_heartbeat.rejected, 2);
  EXPECT_GE(rx.last_heartbeat.received, 3);
  bool malformed = false, nan = false;
  for (int i = 0; i < rx.last_heartbeat.n_counters; ++i) {
    if (rx.last_heartbeat.counter_names[i] == "malformed.TILLER_ODOMETRY")
      malformed = rx.last_heartbeat.counter_values[i] == 1;
    if (rx.last_heartbeat.counter_names[i] == "rejected.odometry.nan")
      nan = rx.last_heartbeat.counter_values[i] == 1;
  }
  EXPECT_TRUE(malformed);
  EXPECT_TRUE(nan);

  // Still alive and still answering.
  const int before = rx.wrenches;
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.wrenches >= before + 5; }, 3.0));
  EXPECT_EQ(waitpid(pid, nullptr, WNOHANG), 0) << "the peer died";

  // SIGTERM: clean exit, status 0.
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

TEST(Live, DefaultTtlIsZero) {
  EXPECT_EQ(with_default_ttl("udpm://239.255.76.67:7667"), "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(with_default_ttl("udpm://239.255.76.67:7667?recv_buf_size=1"),
            "udpm://239.255.76.67:7667?recv_buf_size=1&ttl=0");
  EXPECT_EQ(with_default_ttl("udpm://239.255.76.67:7667?ttl=0"), "udpm://239.255.76.67:7667?ttl=0");
  EXPECT_EQ(with_default_ttl("memq://"), "memq://");
}

}  // namespace
}  // namespace tiller
