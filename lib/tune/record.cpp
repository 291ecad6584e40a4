#include "tune/record.hpp"

#include <tiller/esc_output_t.hpp>
#include <tiller/odometry_t.hpp>

#include <cmath>

#include "core/time.hpp"
#include "runtime/channels.hpp"

namespace tiller::tune {

Record record_from_events(const std::vector<Event>& events, const Vehicle& vehicle,
                          RecordStats* stats) {
  RecordStats st;
  bool truth = false;
  for (const auto& e : events) truth |= e.channel == channels::kGroundTruth;
  st.motion_channel = truth ? channels::kGroundTruth : channels::kOdometry;
  Record r;
  bool have_t0 = false;
  TimeUs t0 = 0;
  const auto seconds = [&](TimeUs t) {
    if (!have_t0) {
      t0 = t;
      have_t0 = true;
    }
    return to_seconds(t - t0);
  };
  std::vector<Wrench> columns;
  for (const auto& th : vehicle.thrusters) columns.push_back(th.wrench_per_newton());
  odometry_t od;
  esc_output_t eo;
  constexpr int kNeeded = int{odometry_t::VALID_VELOCITY} | int{odometry_t::VALID_ATTITUDE};
  for (const auto& e : events) {
    if (e.channel == st.motion_channel) {
      bool ok = decode(e, od) && (truth || (od.valid & kNeeded) == kNeeded);
      for (const double v : od.velocity) ok &= std::isfinite(v);
      const double t = ok ? seconds(od.utime) : 0;
      ok &= r.motion.empty() || t > r.motion.back().t;
      if (!ok) {
        ++st.dropped_motion;
        continue;
      }
      MotionSample s;
      s.t = t;
      for (int i = 0; i < 6; ++i) s.nu[static_cast<std::size_t>(i)] = od.velocity[i];
      r.motion.push_back(s);
      ++st.motion;
    } else if (e.channel == channels::kEscOutput) {
      bool ok = decode(e, eo) && eo.n_channels >= 0 &&
                static_cast<int>(eo.names.size()) == eo.n_channels &&
                static_cast<int>(eo.normalized.size()) == eo.n_channels;
      Wrench w = Wrench::Zero();
      for (int c = 0; ok && c < eo.n_channels; ++c) {
        const auto k = static_cast<std::size_t>(c);
        const int i = vehicle.index_of(eo.names[k]);
        const double n = eo.normalized[k];
        ok &= i >= 0 && std::isfinite(n) && std::fabs(n) <= 1;
        if (!ok || !eo.armed) continue;
        const Thruster& th = vehicle.thrusters[static_cast<std::size_t>(i)];
        w += columns[static_cast<std::size_t>(i)] * th.thrust_from_command(th.reversed ? -n : n);
      }
      const double t = ok ? seconds(eo.utime) : 0;
      ok &= r.targets.empty() || t >= r.targets.back().t;
      if (!ok) {
        ++st.dropped_esc;
        continue;
      }
      r.targets.push_back({t, w});
      ++st.esc;
    }
  }
  if (stats != nullptr) *stats = st;
  return r;
}

}  // namespace tiller::tune
