// Path-following metrics of a run over a polyline path (world NED, m; times s), for tuning
// cross-track laws and turn anticipation (docs/tuning.md):
//   * passage times: for each waypoint in order, the time of the vehicle's closest approach to
//     it, searched from the previous waypoint's passage until the vehicle, having come within a
//     quarter of the next leg's length of the waypoint, is halfway along the next leg;
//   * steady cross-track RMS: the distance to each leg's line from settle_s after the leg began
//     (the passage of its first point) until end_margin_m before its end point along the leg
//     (the next turn's wheel-over and cut inside the corner are the turn's, not the leg's) and
//     at most the passage of its end point, RMS over all legs. The one definition: tiller-score,
//     tiller-run, its sweeps and the closed-loop tests all score with it (docs/tuning.md);
//   * weaving: RMS of the heading rate (rad/s, finite differences of consecutive poses, both in
//     a steady window): a boat holding a straight line, crabbed or not, scores 0; one that
//     hunts about its heading scores its oscillation (amplitude A at w rad/s: A w / sqrt 2);
//   * corner overshoot: at each interior waypoint, the largest distance the vehicle goes beyond
//     the next leg's line on the outside of the turn (the side the previous leg points to),
//     from the previous waypoint's passage until it is halfway along the next leg.
// Lower is better for every number. Legs shorter than settle_s of travel give no steady samples.
#pragma once

#include <vector>

#include "scores/scores.hpp"

namespace tiller::scores {

struct CornerScores {
  std::vector<double> passage;         // s: time of closest approach to each waypoint (-1: never)
  double steady_cross_track_rms = -1;  // m; -1: no steady samples
  int steady_samples = 0;
  std::vector<double> overshoot;  // m, per interior waypoint (>= 0)
  double max_overshoot = 0;       // m
  double weaving = -1;            // rad/s: RMS heading rate in the steady windows; -1: none
};

// The steady windows (above). 60 s and 10 m: the follower's law has settled after a corner
// (the Otter's ILOS / world-frame integral, 10-30 s) and the next corner's wheel-over (up to
// 4 m before it on the Otter, with the drift lead) is left out.
struct SteadyWindow {
  double settle_s = 60;      // s after the passage of a leg's start
  double end_margin_m = 10;  // m before a leg's end point, along the leg
};

// Only poses from `start` to `end` (s) count: pass the path's completion as `end`, so that
// station keeping at the goal afterwards is not scored as path following (the closest approach
// to the goal would otherwise come at the end of the hold, and the hold's manoeuvres count as
// the last leg's cross-track).
CornerScores corner_scores(const std::vector<Pose>& run, const std::vector<Goal>& path,
                           double start, double settle_s = SteadyWindow{}.settle_s,
                           double end = 1e300, double end_margin_m = SteadyWindow{}.end_margin_m);

}  // namespace tiller::scores
