// Test nodes for the runtime tests: a "controller" whose output depends on its inputs, its
// internal state and the told time (so any ordering or timing difference shows in outputs),
// and a "plant" that answers it, so lockstep runs have a closed loop.
#pragma once

#include <tiller/odometry_t.hpp>
#include <tiller/wrench_t.hpp>

#include "core/checks.hpp"
#include "runtime/node.hpp"

namespace tiller::test {

class ToyController : public Node {
 public:
  explicit ToyController(TimeUs period = 20'000) : Node("toy-controller", period) {
    subscribe("TILLER_ODOMETRY", &ToyController::on_odometry);
    nan_ = &counter("rejected.odometry.nan");
  }
  void on_odometry(const odometry_t& m, TimeUs now) {
    if (!all_finite(m.position) || !all_finite(m.velocity)) {
      reject(*nan_);
      return;
    }
    x_ = m.position[0];
    v_ = m.velocity[0];
    last_rx_ = now;
  }
  void on_tick(TimeUs now) override {
    integral_ += (1.0 - x_) * to_seconds(tick_period());
    wrench_t w{};
    w.utime = now;
    w.source = wrench_t::SOURCE_VELOCITY_PID;
    w.valid = true;
    w.tau[0] = 2.0 * (1.0 - x_) - 1.5 * v_ + 0.3 * integral_;
    w.tau[5] = to_seconds(now - last_rx_);  // the time told matters
    publish("TILLER_WRENCH_VELOCITY", w);
  }
  double integral_ = 0, x_ = 0, v_ = 0;
  TimeUs last_rx_ = 0;
  std::int64_t* nan_;
};

class ToyPlant : public Node {
 public:
  explicit ToyPlant(TimeUs period = 10'000) : Node("toy-plant", period) {
    subscribe("TILLER_WRENCH_VELOCITY", &ToyPlant::on_wrench);
  }
  void on_wrench(const wrench_t& w, TimeUs) { force_ = w.tau[0]; }
  void on_tick(TimeUs now) override {
    const double dt = to_seconds(tick_period());
    v_ += (force_ - 0.8 * v_) * dt;
    x_ += v_ * dt;
    odometry_t o{};
    o.utime = now;
    o.position[0] = x_;
    o.velocity[0] = v_;
    publish("TILLER_ODOMETRY", o);
  }
  double x_ = 0, v_ = 0, force_ = 0;
};

}  // namespace tiller::test
