// Prints the issue-34 figures of position hold on the DVL (rov_dvl_scenarios.hpp), for the
// BlueROV2-class ROV and the 6-thruster ROV: the hold in a 0.2 m/s current, the recovery from a
// 20 N lateral step, and a 10 s DVL dropout. A tool that prints figures: nothing is asserted
// here (rov_dvl_hold_test asserts the invariants). Usage: build/bench/rov_hold_figures [VEHICLE]
#include <cstdio>
#include <string>
#include <vector>

#include "control/rov_modes.hpp"
#include "rov_dvl_scenarios.hpp"

using namespace tiller;
using namespace tiller::e2e;

int main(int argc, char** argv) {
  std::vector<std::string> vehicles = {"bluerov2", "seed001_rov6"};
  if (argc > 1) vehicles = {argv[1]};
  for (const std::string& v : vehicles) {
    const HoldFigures h = hold_in_current(v, 0.2);
    std::printf(
        "%s hold, 0.2 m/s current, 30 s: %s; horizontal %.4f m RMS (largest %.4f m) from the "
        "held point, depth %.4f m RMS, heading %.3f deg RMS; estimate off the truth by %.4f m "
        "(its 1-sigma %.4f m)\n",
        v.c_str(), control::rov_mode_words(h.mode), h.rms_m, h.max_m, h.depth_rms_m,
        h.heading_rms_deg, h.estimate_error_m, h.estimate_std_m);
    const StepFigures s = step_recovery(v, 20.0, 0.2);
    std::printf(
        "%s 20 N lateral step while holding in the current (%s at the end): largest excursion %.4f "
        "m at %.2f s, "
        "within 10 %% of it from %.2f s on, %.4f m after 10 s (before the step: %.4f m RMS); truly "
        "%.4f m at most, %.4f m at the end\n",
        v.c_str(), control::rov_mode_words(s.mode), s.peak_m, s.peak_at_s, s.within_10_s, s.final_m,
        s.jitter_m, s.truth_peak_m, s.truth_final_m);
    const DropoutFigures d = dvl_dropout(v, 0.2, 30.0, 10.0);
    std::printf(
        "%s 10 s DVL dropout in the current: fell back %.2f s after it began to %s, drifted "
        "%.3f m, depth within %.4f m and heading within %.3f deg meanwhile; largest thrust change "
        "per 10 ms: steady hold %.3f N, at the fallback %.3f N, at the DVL's return %.3f N; "
        "after it: %s, estimate %s, position_hold.lost %lld\n  reason: %s\n",
        v.c_str(), d.fallback_after_s, control::rov_mode_words(d.mode_during), d.drift_m,
        d.depth_max_err_m, d.heading_max_err_deg, d.steady_step_n, d.fallback_step_n,
        d.recovery_step_n, control::rov_mode_words(d.mode_after),
        d.estimate_valid_after ? "valid" : "invalid", static_cast<long long>(d.lost),
        d.reason.c_str());
  }
  return 0;
}
