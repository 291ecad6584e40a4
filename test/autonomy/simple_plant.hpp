// A small stand-in plant for closed-loop tests of the autonomy alone: the Otter's 3-DOF
// surge-sway-yaw model (otter.py's numbers, docs/adding-a-vehicle.md: M = diag(85.5, 162.5, 42.65),
// D = 77.55, 162.5, 42.65 + quadratic yaw 10 * 42.65 |r| r) moving relative to a constant current,
// with the Otter's two propellers (y = -+0.395 m, +119.7 / -66.7 N, no sway authority) allocated
// directly from the wrench the arbitration selects, and says so as an armed mixer would
// (TILLER_THRUSTER_COMMAND: gate ACTIVE, that source; the controllers integrate only then). It
// stands in for mixer + esc + simulator; the
// full stack (MixerNode, EscNode, SimNode) is what test/autonomy's closed-loop tests use when
// present. World NED, body FRD; explicit Euler at 10 ms (the model is heavily damped).
#pragma once

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/wrench_t.hpp>

#include <algorithm>
#include <cmath>

#include "runtime/channels.hpp"
#include "runtime/node.hpp"

namespace tiller::test {

class SimplePlant : public Node {
 public:
  SimplePlant(double current_speed, double current_from_rad, double n0 = 0, double e0 = 0,
              double psi0 = 0)
      : Node("simple-plant", 10'000), n_(n0), e_(e0), psi_(psi0) {
    // "From" 30 deg: the water flows toward 210 deg.
    vc_n_ = -current_speed * std::cos(current_from_rad);
    vc_e_ = -current_speed * std::sin(current_from_rad);
    subscribe(channels::kWrenchVelocity, &SimplePlant::on_wv);
    subscribe(channels::kWrenchStation, &SimplePlant::on_ws);
    subscribe(channels::kArbitration, &SimplePlant::on_arb);
    status_.strategy = "simple-plant";
  }
  void on_wv(const wrench_t& w, TimeUs) { wv_ = w; }
  void on_ws(const wrench_t& w, TimeUs) { ws_ = w; }
  void on_arb(const arbitration_t& a, TimeUs) { source_ = a.active_source; }

  void on_tick(TimeUs now) override {
    const wrench_t* w = source_ == wrench_t::SOURCE_VELOCITY_PID   ? &wv_
                        : source_ == wrench_t::SOURCE_STATION_KEEP ? &ws_
                                                                   : nullptr;
    double X = 0, N = 0;
    if (w && w->valid) {
      X = w->tau[0];
      N = w->tau[5];
    }
    const double arm = 0.395;
    double tp = X / 2 + N / (2 * arm), ts = X / 2 - N / (2 * arm);
    const double tp_c = std::clamp(tp, -66.7, 119.7), ts_c = std::clamp(ts, -66.7, 119.7);
    const bool reduced = tp_c != tp || ts_c != ts;
    tp = tp_c;
    ts = ts_c;
    // First-order thruster lag, 0.1 s.
    const double dt = 0.01;
    thrust_p_ += (tp - thrust_p_) * dt / 0.1;
    thrust_s_ += (ts - thrust_s_) * dt / 0.1;
    const double Xt = thrust_p_ + thrust_s_, Nt = arm * (thrust_p_ - thrust_s_);
    // Relative velocity.
    const double c = std::cos(psi_), s = std::sin(psi_);
    const double ucb = c * vc_n_ + s * vc_e_, vcb = -s * vc_n_ + c * vc_e_;
    const double ur = u_ - ucb, vr = v_ - vcb;
    const double du = (Xt - 77.55 * ur) / 85.5 + r_ * vr;
    const double dv = (-162.5 * vr) / 162.5 - r_ * ur;
    const double dr = (Nt - 42.65 * r_ - 426.5 * std::abs(r_) * r_) / 42.65;
    u_ += du * dt;
    v_ += dv * dt;
    r_ += dr * dt;
    n_ += (c * u_ - s * v_) * dt;
    e_ += (s * u_ + c * v_) * dt;
    psi_ = std::remainder(psi_ + r_ * dt, 2 * 3.14159265358979323846);
    if (now % 50'000 == 0) {
      odometry_t o{};
      o.valid = odometry_t::VALID_ALL;
      o.utime = now;
      o.position[0] = n_;
      o.position[1] = e_;
      o.orientation[2] = psi_;
      o.velocity[0] = u_;
      o.velocity[1] = v_;
      o.velocity[5] = r_;
      publish(channels::kOdometry, o);
      status_.utime = now;
      status_.source = source_;
      status_.axis_reduced[0] = status_.axis_reduced[5] = reduced;
      status_.axis_unactuated[1] = true;
      publish(channels::kAllocationStatus, status_);
      thruster_command_t cmd{};
      cmd.utime = now;
      cmd.armed = true;
      cmd.source = source_;
      cmd.gate = thruster_command_t::GATE_ACTIVE;
      cmd.arm_allowed = true;
      publish(channels::kThrusterCommand, cmd);
    }
  }

 private:
  double n_, e_, psi_, u_ = 0, v_ = 0, r_ = 0;
  double vc_n_ = 0, vc_e_ = 0;
  double thrust_p_ = 0, thrust_s_ = 0;
  wrench_t wv_{}, ws_{};
  std::int8_t source_ = 0;
  allocation_status_t status_{};
};

}  // namespace tiller::test
