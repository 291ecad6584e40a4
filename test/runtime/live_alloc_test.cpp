// The live receive path allocates nothing: a node under the real LiveExecutor receives a
// 1 kHz stream on two channels (one with a name longer than std::string's 15-character small
// buffer, TILLER_THRUSTER_COMMAND, which lcm-cpp's callbacks would copy to the heap), ticks
// and publishes, and after a warm-up not one operator new runs in this process while 2,000
// messages come in. The stream comes from a child process over udpm, inside the private
// network namespace of tools/netns-run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/wrench_t.hpp>

#include "alloc_count.hpp"
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

// The child: publishes odometry and a thruster command every millisecond until killed.
[[noreturn]] void stream() {
  lcm::LCM l(kUrl);
  if (!l.good()) _exit(3);
  odometry_t o{};
  thruster_command_t c{};
  c.n_thrusters = 2;
  c.names = {"port", "starboard"};
  c.command = {0.1, -0.1};
  for (;;) {
    o.utime += 1000;
    c.utime = o.utime;
    l.publish("TILLER_ODOMETRY", &o);
    l.publish("TILLER_THRUSTER_COMMAND", &c);
    usleep(1000);
  }
}

TEST(LiveAllocation, ReceivingAllocatesNothingAfterWarmUp) {
  LiveExecutor ex(kUrl);
  Counting node(ex);
  ex.add(node);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) stream();
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

}  // namespace
}  // namespace tiller
