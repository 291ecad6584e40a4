#include "scores/path_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "core/angles.hpp"

namespace tiller::scores {
namespace {

struct Leg {
  double n0, e0, tn, te, len;  // start, unit direction, length
};

Leg leg(const Goal& a, const Goal& b) {
  const double dn = b.north - a.north, de = b.east - a.east;
  const double len = std::hypot(dn, de);
  return len > 0 ? Leg{a.north, a.east, dn / len, de / len, len} : Leg{a.north, a.east, 1, 0, 0};
}

}  // namespace

CornerScores corner_scores(const std::vector<Pose>& run, const std::vector<Goal>& path,
                           double start, double settle_s, double end, double end_margin_m) {
  CornerScores c;
  const std::size_t n = path.size();
  c.passage.assign(n, -1);
  // Passage times: closest approach, searched forward from the previous passage. The search for
  // waypoint k stops halfway along the next leg (a later pass does not count).
  std::size_t from = 0;
  while (from < run.size() && run[from].t < start) ++from;
  for (std::size_t k = 0; k < n && from < run.size(); ++k) {
    double best = 1e300;
    std::size_t at = from;
    for (std::size_t i = from; i < run.size() && run[i].t <= end; ++i) {
      const double d = std::hypot(run[i].north - path[k].north, run[i].east - path[k].east);
      if (d < best) {
        best = d;
        at = i;
      }
      if (k + 1 < n) {
        // Past the halfway point of the next leg, having come within a quarter of it of the
        // waypoint (a hairpin's next leg runs back over the previous one): the approach is over.
        const Leg l = leg(path[k], path[k + 1]);
        const double s = (run[i].north - l.n0) * l.tn + (run[i].east - l.e0) * l.te;
        if (best < l.len / 4 && s > l.len / 2) break;
      }
    }
    c.passage[k] = run[at].t;
    from = at;
  }
  // Steady cross-track and weaving.
  double sum = 0, rate_sum = 0;
  int rates = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (c.passage[k] < 0 || c.passage[k + 1] < 0) continue;
    const Leg l = leg(path[k], path[k + 1]);
    const Pose* prev = nullptr;  // the previous pose, when it was in the window
    for (const auto& p : run) {
      const double s = (p.north - l.n0) * l.tn + (p.east - l.e0) * l.te;
      if (p.t < c.passage[k] + settle_s || p.t > c.passage[k + 1] || p.t > end ||
          s > l.len - end_margin_m) {
        prev = nullptr;
        continue;
      }
      const double e = -(p.north - l.n0) * l.te + (p.east - l.e0) * l.tn;
      sum += e * e;
      ++c.steady_samples;
      if (prev != nullptr && p.t > prev->t) {
        const double r = angle_diff(p.heading, prev->heading) / (p.t - prev->t);
        rate_sum += r * r;
        ++rates;
      }
      prev = &p;
    }
  }
  if (c.steady_samples > 0) c.steady_cross_track_rms = std::sqrt(sum / c.steady_samples);
  if (rates > 0) c.weaving = std::sqrt(rate_sum / rates);
  // Corner overshoot.
  for (std::size_t k = 1; k + 1 < n; ++k) {
    double worst = 0;
    if (c.passage[k - 1] >= 0 && c.passage[k] >= 0) {
      const Leg a = leg(path[k - 1], path[k]), b = leg(path[k], path[k + 1]);
      double on = -b.te, oe = b.tn;  // right normal of the next leg
      if (a.tn * on + a.te * oe < 0) {
        on = -on;
        oe = -oe;
      }
      for (const auto& p : run) {
        if (p.t < c.passage[k - 1]) continue;
        if (p.t > end) break;
        const double s = (p.north - b.n0) * b.tn + (p.east - b.e0) * b.te;
        if (p.t > c.passage[k] && s > b.len / 2) break;
        worst = std::max(worst, (p.north - b.n0) * on + (p.east - b.e0) * oe);
      }
    }
    c.overshoot.push_back(worst);
    c.max_overshoot = std::max(c.max_overshoot, worst);
  }
  return c;
}

}  // namespace tiller::scores
