// Position hold on the DVL, the issue-34 scenarios (rov_rig.hpp with dvl_nav: the simulator's
// sensors with the DVL -> tiller-nav's dead reckoning -> tiller-rov-control -> mixer -> ESC ->
// simulator, one process on simulated time, the stick centred after arming). Shared by
// rov_dvl_hold_test (asserts) and bench/rov_hold_figures (prints). Each returns its figures:
//   hold_in_current   position hold in a constant current: the vehicle's true horizontal distance
//                     from the held point (m, RMS and largest; the held point is in tiller-nav's
//                     frame, so the dead reckoning's drift counts against the hold), depth and
//                     heading errors, and the estimate's own error against the truth
//   step_recovery     a lateral (body sway) step force while holding: the largest excursion
//                     along the force and the time until it stays within 10 % of that largest
//   dvl_dropout       the DVL silent for a while: when position hold fell back and to what, the
//                     drift meanwhile, the largest thrust change per 10 ms around the fallback
//                     and the DVL's return against the steady hold's, and the mode after it
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rov_rig.hpp"

namespace tiller::e2e {

inline RovSetup dvl_setup(const std::string& vehicle, double current_m_s) {
  RovSetup s = rov_setup(vehicle);
  s.dvl_nav = true;
  s.current_m_s = current_m_s;
  return s;
}

// Arms, lets tiller-nav start (the DVL's first velocity starts dead reckoning), then asks for
// position hold and lets it settle for `settle_ms`.
inline void start_hold(RovRig& r, int settle_ms) {
  r.run(2'000);
  r.command(controller_mode_t::POSITION_HOLD);
  r.run(settle_ms);
}

inline double horizontal_error(const RovRig& r) {
  const auto& a = r.rov.axes();
  return std::hypot(r.eta()[0] - a.target(0), r.eta()[1] - a.target(1));
}

struct HoldFigures {
  std::int8_t mode = -1;
  double rms_m = 0, max_m = 0;  // truth from the held point
  double depth_rms_m = 0;       // truth from the held depth
  double heading_rms_deg = 0;   // truth from the held heading
  double estimate_error_m = 0;  // |estimate - truth| horizontally at the end
  double estimate_std_m = 0;    // the estimate's own 1-sigma (north) at the end
};

inline HoldFigures hold_in_current(const std::string& vehicle, double current_m_s,
                                   int measure_ms = 30'000) {
  RovRig r(dvl_setup(vehicle, current_m_s));
  start_hold(r, 15'000);
  HoldFigures f;
  f.mode = r.rov.mode();
  std::vector<double> ne, d, h;
  r.run(measure_ms, [&] {
    const auto& a = r.rov.axes();
    ne.push_back(horizontal_error(r));
    f.max_m = std::max(f.max_m, ne.back());
    d.push_back(r.depth() - a.target(2));
    h.push_back(angle_diff(r.eta()[5], a.target(5)));
  });
  f.rms_m = rms(ne);
  f.depth_rms_m = rms(d);
  f.heading_rms_deg = rad_to_deg(rms(h));
  const odometry_t& o = r.nav->last_odometry();
  f.estimate_error_m = std::hypot(o.position[0] - r.eta()[0], o.position[1] - r.eta()[1]);
  f.estimate_std_m = std::sqrt(o.pose_covariance[0]);
  if (r.rov.mode() != controller_mode_t::POSITION_HOLD) f.mode = r.rov.mode();
  return f;
}

struct StepFigures {
  std::int8_t mode = -1;
  double peak_m = 0;        // largest excursion along the force from where the vehicle was
  double peak_at_s = 0;     // after the step
  double within_10_s = -1;  // after the step, the excursion stays within 10 % of the peak
  double final_m = 0;       // excursion at the end
  double jitter_m = 0;      // the same measure's RMS over the 5 s before the step (the floor)
  double truth_peak_m = 0, truth_final_m = 0;  // the true displacement along the force
};

// `force_n` along the body's sway axis (starboard), after the hold has settled, held;
// `current_m_s` as in the hold. The excursion is tiller-nav's position along the force from where
// it was at the step (what the controller holds; the true displacement adds the dead reckoning's
// slow drift, about 0.5 mm/s here, and is reported beside it), averaged over 0.2 s (the hold's
// own 10 ms jitter left out).
inline StepFigures step_recovery(const std::string& vehicle, double force_n, double current_m_s,
                                 int after_ms = 10'000) {
  RovRig r(dvl_setup(vehicle, current_m_s));
  start_hold(r, 10'000);
  const double psi = r.eta()[5];
  const double dn = -std::sin(psi), de = std::cos(psi);  // starboard, NED
  const auto along = [&] {
    const odometry_t& o = r.nav->last_odometry();
    return dn * o.position[0] + de * o.position[1];
  };
  std::vector<double> before;
  r.run(5'000, [&] { before.push_back(along()); });
  double mean = 0;
  for (double x : before) mean += x;
  mean /= static_cast<double>(before.size());
  StepFigures f;
  for (double& x : before) x -= mean;
  const auto smooth = [](const std::vector<double>& v) {
    std::vector<double> o(v.size());
    double sum = 0;
    for (std::size_t k = 0; k < v.size(); ++k) {
      sum += v[k];
      if (k >= 20) sum -= v[k - 20];
      o[k] = sum / static_cast<double>(std::min<std::size_t>(k + 1, 20));
    }
    return o;
  };
  f.jitter_m = rms(smooth(before));
  r.sim.set_disturbance(sim::Vector3(dn * force_n, de * force_n, 0.0));
  const double x0 = along(), t0 = dn * r.eta()[0] + de * r.eta()[1];
  std::vector<double> raw;
  r.run(after_ms, [&] {
    raw.push_back(along() - x0);
    const double t = dn * r.eta()[0] + de * r.eta()[1] - t0;
    f.truth_peak_m = std::max(f.truth_peak_m, t);
    f.truth_final_m = t;
  });
  const std::vector<double> ex = smooth(raw);
  f.mode = r.rov.mode();
  const auto peak = std::max_element(ex.begin(), ex.end());
  f.peak_m = *peak;
  f.peak_at_s = 0.01 * static_cast<double>(peak - ex.begin() + 1);
  std::size_t last_out = 0;
  for (std::size_t k = 0; k < ex.size(); ++k)
    if (std::fabs(ex[k]) > 0.1 * f.peak_m) last_out = k + 1;
  if (last_out < ex.size()) f.within_10_s = 0.01 * static_cast<double>(last_out + 1);
  f.final_m = ex.back();
  return f;
}

struct DropoutFigures {
  std::int8_t mode_during = -1, mode_after = -1;
  double fallback_after_s = -1;  // after the dropout began (the simulator's time)
  double drift_m = 0;            // true horizontal distance moved while the DVL was silent
  double depth_max_err_m = 0;    // |depth - held depth| during the dropout
  double heading_max_err_deg = 0;
  double steady_step_n = 0;    // largest thrust change per 10 ms over 5 s of steady hold
  double fallback_step_n = 0;  // ... over the 3 s from the dropout's start
  double recovery_step_n = 0;  // ... over the 3 s from the DVL's return
  bool estimate_valid_after = false;
  std::int64_t lost = 0;  // position_hold.lost
  std::string reason;     // the arbitration's reason during the dropout
};

inline DropoutFigures dvl_dropout(const std::string& vehicle, double current_m_s, double start_s,
                                  double duration_s) {
  RovSetup s = dvl_setup(vehicle, current_m_s);
  s.dvl_outages.push_back({from_seconds(start_s), from_seconds(start_s + duration_s)});
  RovRig r(s);
  start_hold(r, 0);
  // Settle until 5 s before the dropout (the rig's time: arming took a little), then 5 s steady.
  r.run(static_cast<int>((from_seconds(start_s - 5.0) - r.f.t) / 1000) / 10 * 10);
  DropoutFigures f;
  f.steady_step_n = thrust_step(r, 5'000);  // up to the dropout's start
  const double n0 = r.eta()[0], e0 = r.eta()[1];
  const TimeUs outage_at = from_seconds(start_s);
  const auto watch = [&] {
    if (f.fallback_after_s < 0 && r.rov.mode() != controller_mode_t::POSITION_HOLD)
      f.fallback_after_s = to_seconds(r.f.t - outage_at);
    if (f.fallback_after_s >= 0) {
      const auto& a = r.rov.axes();
      f.depth_max_err_m = std::max(f.depth_max_err_m, std::fabs(r.depth() - a.target(2)));
      f.heading_max_err_deg = std::max(f.heading_max_err_deg,
                                       std::fabs(rad_to_deg(angle_diff(r.eta()[5], a.target(5)))));
    }
  };
  f.fallback_step_n = thrust_step(r, 3'000, watch);
  f.mode_during = r.rov.mode();
  f.reason = r.rov.reason();
  const int rest_ms = static_cast<int>(duration_s * 1000) - 3'000;
  r.run(rest_ms, watch);
  f.drift_m = std::hypot(r.eta()[0] - n0, r.eta()[1] - e0);
  f.recovery_step_n = thrust_step(r, 3'000);
  f.mode_after = r.rov.mode();
  f.estimate_valid_after = (r.nav->last_odometry().valid & odometry_t::VALID_POSITION) != 0;
  f.lost = r.rov.counter_value("position_hold.lost");
  return f;
}

}  // namespace tiller::e2e
