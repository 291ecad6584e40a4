// The live receive path allocates nothing: a node under the real LiveExecutor receives a
// 1 kHz stream on two channels (one with a name longer than std::string's 15-character small
// buffer, TILLER_THRUSTER_COMMAND, which lcm-cpp's callbacks would copy to the heap), ticks
// and publishes, and after a warm-up not one operator new runs in this process while 2,000
// messages come in. The stream comes from a child process over udpm, inside the private
// network namespace of tools/netns-run. The same with message signing on (a key, require_signed):
// every message is checked and every output signed, and unsigned ones among them are refused
// and counted, still without an allocation.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/wrench_t.hpp>

#include "alloc_count.hpp"
#include "auth/trailer.hpp"
#include "runtime/live.hpp"

namespace tiller {
namespace {

const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

class Counting : public Node {
 public:
  explicit Counting(LiveExecutor& ex) : Node("alloc-probe", 10'000), ex_(ex) {
    subscribe("TILLER_ODOMETRY", &Counting::on_odometry);
    subscribe("TILLER_THRUSTER_COMMAND", &Counting::on_command);
    advertise<wrench_t>("TILLER_WRENCH_VELOCITY");
  }
  void on_odometry(const odometry_t& m, TimeUs) { x_ += m.position[0]; }
  void on_command(const thruster_command_t& m, TimeUs) {
    if (m.n_thrusters > 0) x_ += m.command[0];
  }
  void on_tick(TimeUs now) override {
    if (start_ == 0) start_ = now;
    wrench_t w{};
    w.utime = now;
    w.tau[0] = x_;
    publish("TILLER_WRENCH_VELOCITY", w);
    if (base_allocs_ < 0 && received() >= 500) {  // warm-up done
      base_allocs_ = test::allocations();
      base_rx_ = received();
    }
    if (base_allocs_ >= 0 && received() >= base_rx_ + 2000) {
      end_allocs_ = test::allocations();
      end_rx_ = received();
      ex_.stop();
    }
    if (now - start_ > 30 * kUsPerSecond) ex_.stop();  // the stream never came: fail below
  }
  LiveExecutor& ex_;
  double x_ = 0;
  TimeUs start_ = 0;
  long base_allocs_ = -1, end_allocs_ = -1;
  std::int64_t base_rx_ = 0, end_rx_ = 0;
};

auth::Key test_key() {
  auth::Key k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(3 * i);
  k.id = auth::key_id(k.bytes);
  return k;
}

// The child: publishes odometry and a thruster command every millisecond until killed; with a
// signer, signed, plus an unsigned odometry every tenth time.
template <class Msg>
void send(lcm::LCM& l, const char* channel, const Msg& m, auth::Signer* signer) {
  std::uint8_t buf[512];
  const int n = m.encode(buf, 0, static_cast<int>(sizeof buf) - auth::kTrailerSize);
  int size = n;
  if (signer) {
    timespec ts{};
    clock_gettime(CLOCK_REALTIME, &ts);
    signer->sign(channel, buf, n, ts.tv_sec * kUsPerSecond + ts.tv_nsec / 1000, buf + n);
    size += auth::kTrailerSize;
  }
  l.publish(channel, buf, static_cast<unsigned>(size));
}

[[noreturn]] void stream(bool sign) {
  lcm::LCM l(kUrl);
  if (!l.good()) _exit(3);
  auth::Signer signer(test_key(), "streamer");
  auth::Signer* s = sign ? &signer : nullptr;
  odometry_t o{};
  thruster_command_t c{};
  c.n_thrusters = 2;
  c.names = {"port", "starboard"};
  c.command = {0.1, -0.1};
  for (int i = 0;; ++i) {
    o.utime += 1000;
    c.utime = o.utime;
    send(l, "TILLER_ODOMETRY", o, s);
    send(l, "TILLER_THRUSTER_COMMAND", c, s);
    if (sign && i % 10 == 0) send(l, "TILLER_ODOMETRY", o, nullptr);
    usleep(1000);
  }
}

TEST(LiveAllocation, ReceivingAllocatesNothingAfterWarmUp) {
  LiveExecutor ex(kUrl);
  Counting node(ex);
  ex.add(node);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) stream(false);
  const int status = ex.run();
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  EXPECT_EQ(status, 0);
  ASSERT_GE(node.base_allocs_, 0) << "warm-up never finished (received " << node.received() << ")";
  ASSERT_GE(node.end_allocs_, 0) << "stream stopped (received " << node.received() << ")";
  std::printf("%lld messages after warm-up, %ld heap allocations\n",
              static_cast<long long>(node.end_rx_ - node.base_rx_),
              node.end_allocs_ - node.base_allocs_);
  EXPECT_EQ(node.end_allocs_ - node.base_allocs_, 0);
  EXPECT_EQ(node.rejected(), 0);
}

TEST(LiveAllocation, SigningAndCheckingAllocateNothingAfterWarmUp) {
  auth::Policy policy;
  policy.key = test_key();
  policy.require_signed = true;
  LiveExecutor ex(kUrl, policy);
  Counting node(ex);
  ex.add(node);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) stream(true);
  const int status = ex.run();
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  EXPECT_EQ(status, 0);
  ASSERT_GE(node.base_allocs_, 0) << "warm-up never finished (received " << node.received() << ")";
  ASSERT_GE(node.end_allocs_, 0) << "stream stopped (received " << node.received() << ")";
  std::printf("signed: %lld messages after warm-up, %ld heap allocations, %lld unsigned refused\n",
              static_cast<long long>(node.end_rx_ - node.base_rx_),
              node.end_allocs_ - node.base_allocs_,
              static_cast<long long>(node.counter_value("rejected.auth.unsigned")));
  EXPECT_EQ(node.end_allocs_ - node.base_allocs_, 0);
  EXPECT_GT(node.counter_value("rejected.auth.unsigned"), 100);
  EXPECT_EQ(node.rejected(), node.counter_value("rejected.auth.unsigned"));
  EXPECT_EQ(node.counter_value("rejected.auth.replay"), 0);
  EXPECT_EQ(node.counter_value("rejected.auth.bad_mac"), 0);
}

}  // namespace
}  // namespace tiller
