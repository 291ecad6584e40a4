// A peer process for live_fault_test: one node under the live executor that misbehaves on
// purpose, so the test can see what the executor does about it. Every mode prints
// "shutdown <utime>" from the node's shutdown() and "exit <status>" before returning.
//   fault_peer tick URL     on_tick throws from the third tick on (repeated tick failure)
//   fault_peer message URL  the TILLER_ODOMETRY handler throws on every message
//   fault_peer fd URL       an fd callback (a pipe that stays readable) throws every time
//   fault_peer timing URL   a well-behaved 10 ms node; shutdown() also prints
//                           "ticks N offgrid K missed M first T0 last T1" (K: ticks told a
//                           time off the grid; M: the executor's ticks.missed)
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include <tiller/odometry_t.hpp>
#include <tiller/wrench_t.hpp>

#include "runtime/live.hpp"

namespace {

class FaultNode : public tiller::Node {
 public:
  FaultNode(std::string mode, tiller::TimeUs period)
      : Node("fault-peer", period), mode_(std::move(mode)) {
    subscribe("TILLER_ODOMETRY", &FaultNode::on_odometry);
    advertise<tiller::wrench_t>("TILLER_WRENCH_VELOCITY");
  }
  void on_odometry(const tiller::odometry_t&, tiller::TimeUs) {
    if (mode_ == "message") throw std::runtime_error("handler refuses odometry");
  }
  void on_tick(tiller::TimeUs now) override {
    ++ticks_;
    if (now % tick_period() != 0) ++offgrid_;
    if (first_ < 0) first_ = now;
    last_ = now;
    if (mode_ == "tick" && ticks_ >= 3) throw std::runtime_error("on_tick broke");
    tiller::wrench_t w{};
    w.utime = now;
    publish("TILLER_WRENCH_VELOCITY", w);
  }
  void shutdown(tiller::TimeUs now) override {
    std::printf("shutdown %lld\n", static_cast<long long>(now));
    if (mode_ == "timing")
      std::printf("ticks %lld offgrid %lld missed %lld first %lld last %lld\n", ticks_, offgrid_,
                  static_cast<long long>(counter_value("ticks.missed")), first_, last_);
    std::fflush(stdout);
  }

 private:
  std::string mode_;
  long long ticks_ = 0, offgrid_ = 0, first_ = -1, last_ = -1;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fault_peer tick|message|fd|timing LCM_URL\n");
    return 2;
  }
  const std::string mode = argv[1];
  FaultNode node(mode, mode == "timing" ? 10'000 : 50'000);
  tiller::LiveExecutor ex(argv[2]);
  ex.add(node);
  int p[2] = {-1, -1};
  if (mode == "fd") {
    if (pipe(p) != 0) return 2;
    if (write(p[1], "x", 1) != 1) return 2;  // never read: stays readable
    ex.add_fd(p[0], [](tiller::TimeUs) { throw std::runtime_error("fd callback broke"); });
  }
  const int status = ex.run();
  std::printf("exit %d\n", status);
  std::fflush(stdout);
  return status;
}
