// The live executor's error policy and timing rules, with a real process (fault_peer) over udpm
// inside the private network namespace of tools/netns-run. Counts and exit statuses are
// checked, never timings:
//   * on_tick throwing repeatedly: every node's shutdown() runs, exit status 3;
//   * an fd callback throwing repeatedly: the same;
//   * a handler throwing on every message: the process keeps running, counts
//     exception.message, says FAULT in its heartbeat, and SIGINT still ends in shutdown(), 0;
//   * ticks are told grid times (t = k * period), heartbeats fall on the tick grid once per
//     second of the node's time, and SIGINT as well as SIGTERM end in shutdown() with status 0.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/wrench_t.hpp>

namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

struct Peer {
  pid_t pid = -1;
  int out = -1;  // the peer's stdout
  std::string text;
  // Reads what the peer printed, waits for it and returns its exit status (-1: signalled).
  int wait() {
    char buf[4096];
    ssize_t n;
    while ((n = read(out, buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(n));
    close(out);
    int st = 0;
    waitpid(pid, &st, 0);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
};

Peer start(const char* mode) {
  int p[2];
  EXPECT_EQ(pipe(p), 0);
  Peer peer;
  peer.pid = fork();
  if (peer.pid == 0) {
    dup2(p[1], 1);
    close(p[0]);
    close(p[1]);
    execl(TILLER_TEST_BIN_DIR "/runtime_fault_peer", "runtime_fault_peer", mode, kUrl, nullptr);
    _exit(127);
  }
  close(p[1]);
  peer.out = p[0];
  return peer;
}

struct Rx {
  void on_hb(const lcm::ReceiveBuffer*, const std::string&, const tiller::heartbeat_t* m) {
    hbs.push_back(*m);
  }
  void on_wrench(const lcm::ReceiveBuffer*, const std::string&, const tiller::wrench_t* m) {
    wrench_times.push_back(m->utime);
  }
  std::vector<tiller::heartbeat_t> hbs;
  std::vector<std::int64_t> wrench_times;
};

bool pump_until(lcm::LCM& l, const std::function<bool()>& pred, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    l.handleTimeout(20);
  }
  return pred();
}

std::int64_t counter(const tiller::heartbeat_t& h, const std::string& name) {
  for (int i = 0; i < h.n_counters; ++i)
    if (h.counter_names[i] == name) return h.counter_values[i];
  return 0;
}

TEST(LiveFault, RepeatedTickExceptionShutsDownWithStatus3) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_HEARTBEAT_FAULT_PEER", &Rx::on_hb, &rx);
  Peer p = start("tick");
  const int status = p.wait();  // ends by itself
  EXPECT_EQ(status, 3) << p.text;
  EXPECT_NE(p.text.find("shutdown "), std::string::npos) << p.text;
  EXPECT_NE(p.text.find("exit 3"), std::string::npos) << p.text;
  // Its last heartbeat (published just before shutdown) says FAULT and counts 3 failed ticks. (A
  // 1 Hz heartbeat between the first and the third failure may say FAULT with fewer: the queued
  // heartbeats are read in order, so wait for the one with 3.)
  ASSERT_TRUE(pump_until(
      l,
      [&] {
        return !rx.hbs.empty() && rx.hbs.back().state == 2 &&
               counter(rx.hbs.back(), "exception.tick") == 3;
      },
      2.0))
      << (rx.hbs.empty() ? std::string("no heartbeat")
                         : "last: state " + std::to_string(rx.hbs.back().state) + ", ticks " +
                               std::to_string(counter(rx.hbs.back(), "exception.tick")));
  EXPECT_NE(rx.hbs.back().status.find("on_tick broke"), std::string::npos);
}

TEST(LiveFault, RepeatedFdCallbackExceptionShutsDownWithStatus3) {
  Peer p = start("fd");
  EXPECT_EQ(p.wait(), 3) << p.text;
  EXPECT_NE(p.text.find("shutdown "), std::string::npos) << p.text;
}

TEST(LiveFault, ThrowingHandlerIsCountedAndTheProcessKeepsRunning) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_HEARTBEAT_FAULT_PEER", &Rx::on_hb, &rx);
  l.subscribe("TILLER_WRENCH_VELOCITY", &Rx::on_wrench, &rx);
  Peer p = start("message");
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.wrench_times.size() >= 3; }, 5.0))
      << "the peer never published";
  tiller::odometry_t o{};
  for (int i = 0; i < 5; ++i) l.publish("TILLER_ODOMETRY", &o);
  ASSERT_TRUE(pump_until(
      l, [&] { return !rx.hbs.empty() && counter(rx.hbs.back(), "exception.message") >= 5; }, 4.0))
      << "no heartbeat counted the handler's exceptions";
  EXPECT_EQ(counter(rx.hbs.back(), "exception.message"), 5);
  EXPECT_EQ(rx.hbs.back().rejected, 5);
  EXPECT_EQ(rx.hbs.back().state, tiller::heartbeat_t::STATE_FAULT);
  const std::size_t before = rx.wrench_times.size();
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.wrench_times.size() >= before + 5; }, 3.0))
      << "the peer stopped ticking after the exceptions";
  EXPECT_EQ(waitpid(p.pid, nullptr, WNOHANG), 0) << "the peer died";
  kill(p.pid, SIGINT);
  EXPECT_EQ(p.wait(), 0) << p.text;
  EXPECT_NE(p.text.find("shutdown "), std::string::npos) << p.text;
}

void check_timing(int sig) {
  lcm::LCM l(kUrl);
  ASSERT_TRUE(l.good()) << "run under tools/netns-run";
  Rx rx;
  l.subscribe("TILLER_HEARTBEAT_FAULT_PEER", &Rx::on_hb, &rx);
  l.subscribe("TILLER_WRENCH_VELOCITY", &Rx::on_wrench, &rx);
  Peer p = start("timing");
  ASSERT_TRUE(pump_until(
      l, [&] { return rx.hbs.size() >= 3; }, 10.0))
      << "fewer than 3 heartbeats";
  kill(p.pid, sig);
  EXPECT_EQ(p.wait(), 0) << p.text;
  EXPECT_NE(p.text.find("shutdown "), std::string::npos) << p.text;
  long long ticks = -1, offgrid = -1, missed = -1, first = 0, last = 0;
  const auto at = p.text.find("ticks ");
  ASSERT_NE(at, std::string::npos) << p.text;
  ASSERT_EQ(
      std::sscanf(p.text.c_str() + at, "ticks %lld offgrid %lld missed %lld first %lld last %lld",
                  &ticks, &offgrid, &missed, &first, &last),
      5);
  std::printf(
      "signal %d: %lld ticks, %lld off the grid, %lld missed, %zu wrenches, %zu heartbeats\n", sig,
      ticks, offgrid, missed, rx.wrench_times.size(), rx.hbs.size());
  EXPECT_GT(ticks, 100);
  EXPECT_EQ(offgrid, 0);
  // Every grid point from the first tick to the last was either told or counted as missed.
  EXPECT_EQ(ticks + missed, (last - first) / 10'000 + 1);
  // Published tick times are on the 10 ms grid and strictly increasing.
  for (std::size_t i = 0; i < rx.wrench_times.size(); ++i) {
    EXPECT_EQ(rx.wrench_times[i] % 10'000, 0) << "wrench " << i;
    if (i > 0) {
      EXPECT_GT(rx.wrench_times[i], rx.wrench_times[i - 1]);
    }
  }
  // One heartbeat per second of the node's time, each on the tick grid; "ticks.missed" (if a
  // loaded machine made the loop late) accounts for every grid point that was not told.
  for (std::size_t i = 0; i < rx.hbs.size(); ++i) {
    EXPECT_EQ(rx.hbs[i].utime % 10'000, 0);
    if (i > 0) {
      EXPECT_EQ(rx.hbs[i].utime / 1'000'000, rx.hbs[i - 1].utime / 1'000'000 + 1);
    }
    EXPECT_EQ(rx.hbs[i].state, tiller::heartbeat_t::STATE_OK);
  }
}

TEST(LiveTiming, TicksOnTheGridAndSigtermEndsInShutdown) {
  check_timing(SIGTERM);
}
TEST(LiveTiming, TicksOnTheGridAndSigintEndsInShutdown) {
  check_timing(SIGINT);
}

}  // namespace
