// tiller-score's report: the scores of a run (lib/scores/scores.hpp) from its recorded messages,
// and the lines tiller-score prints. The path is the first TILLER_PATH (or the mission's
// waypoints when given); the pose is TILLER_GROUND_TRUTH when the run has it, else
// TILLER_ODOMETRY; completion is the first TILLER_PATH_PROGRESS of that path saying complete.
// With both (a simulated run on estimated state) the path is also scored on the odometry, the
// pose the path follower followed: the controller's quality apart from the estimator's.
// Used by tiller-score (from a log) and tiller-run (from the lockstep run's messages), so both
// print the same numbers for the same run.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "runtime/event.hpp"
#include "scores/path_metrics.hpp"
#include "scores/scores.hpp"

namespace tiller::scores {

struct RunScores {
  std::string pose_channel;  // TILLER_GROUND_TRUTH or TILLER_ODOMETRY
  std::size_t samples = 0;   // poses scored
  std::vector<Goal> path;    // as followed (path_as_followed)
  PathScores path_scores;
  // Steady cross-track, corner overshoot and weaving (path_metrics.hpp: the one definition) up to
  // the path's completion (the end of the log when not completed).
  CornerScores corners;
  double start = 0;              // s: first TILLER_PATH (else the first pose)
  double end = 0;                // s: last pose
  double station_keeping = -1;   // VRX station keeping from completion to the end; -1: none
  double station_keeping_s = 0;  // s of it
  std::vector<Pose> poses;       // the poses scored
  // With both TILLER_ODOMETRY and TILLER_GROUND_TRUTH (a simulated run on estimated state):
  // each odometry sample against the truth interpolated to its time (within the truth's span).
  std::size_t estimation_samples = 0;
  double position_error_rms = -1, position_error_max = -1;  // m, horizontal
  double heading_error_rms = -1;                            // rad
  // The same from the mission's start (the first TILLER_PATH) on: what the vehicle flew on. A
  // mission behind tiller-mission's start gate starts once the filter has converged; the whole
  // run's figures above carry the convergence from the first fix (-1: no sample after it).
  double mission_position_error_rms = -1, mission_heading_error_rms = -1;  // m, rad
  // With both: the path scored on the odometry poses (estimate_poses), with the same start and
  // completion: cross-track to the path as the follower followed it from the estimate, waypoints
  // reached by the estimate within the visit radius, time to complete (the follower's completion;
  // without one, when the estimate reached the last waypoint). On truth odometry (the estimate
  // is the truth: estimated() false) the same numbers as path_scores.
  std::vector<Pose> estimate_poses;
  std::vector<Goal> estimate_path;  // path_as_followed from the estimate
  std::optional<PathScores> estimate_path_scores;
  std::optional<CornerScores> estimate_corners;
  // The odometry is an estimate (differs from the truth by more than 1 um somewhere), not the
  // truth re-published (which the interpolation puts within about 1e-18 m of it).
  bool estimated() const { return estimation_samples > 0 && position_error_max > 1e-6; }
};

// The estimation error of `estimate` against `truth` (both in time order): RMS and largest
// horizontal position error, RMS heading error (wrapped), over the estimates within the truth's
// time span. Fills the estimation_* fields of `r`, and mission_* over the estimates at or after
// `start` (s).
void score_estimation(const std::vector<Pose>& estimate, const std::vector<Pose>& truth,
                      RunScores& r, double start = 0);

// The events in time order (a log, or what a lockstep run published). `mission_path`: the
// waypoints to score against (empty: the first TILLER_PATH's). Throws std::runtime_error when
// there is no path or no pose.
RunScores score_events(const std::vector<Event>& events,
                       const std::vector<Goal>& mission_path = {});

// The channels score_events reads (a regex for read_log).
inline constexpr const char* kScoredChannels = "TILLER_(GROUND_TRUTH|ODOMETRY|PATH|PATH_PROGRESS)";

// tiller-score's lines ("pose from ...", "waypoints ...", ..., "steady cross-track ...", "corner
// overshoot ...", "weaving ...", "VRX station keeping ..."); on estimated state also
// "estimation error ..." and "on the estimate ...".
void print_scores(const RunScores& s, std::FILE* out);

}  // namespace tiller::scores
