// mission::Sequencer: a mission's items in flight (docs/missions.md "In flight"), as legs the path
// follower flies one at a time. A leg is a path from where the previous one ended (the first:
// from the vehicle) through consecutive waypoints, speed changes and jumps, up to an item that
// needs the vehicle to stop there:
//   loiter with a time   the leg ends at the point; when the follower says it is complete
//                        (station keeping holds its end), the time counts, then the next leg;
//   loiter for ever      the leg ends at the point and the mission with it (held there);
//   return home          a leg to home or the nearest rally point (nearer to the leg's start),
//                        then return_end: hold (station keeping) or stop;
//   stop                 a leg to the point (none: ends where it is), then stop;
//   the last item        the mission ends, holding the last point.
// Stop means an operator RELEASE: the follower drops the path and the mixer disarms (neutral),
// the one existing path (docs/safety.md). Speeds: speeds[k] is the along-path speed of the
// segment from point k (m/s; 0: the follower's max_speed), from the latest speed item before it.
// Consecutive points within kSamePointM are one. Jumps: a jump with repeats left goes on at its
// target within the same leg (a leg is capped at kMaxLegPoints: a jump for ever flies leg after
// leg). Fence: on_position() with the vehicle outside the fence (mission/fence.hpp) while the
// mission runs triggers fence_action once: hold (an operator ABORT: hold where the vehicle is),
// return (a leg home from there, then return_end) or neutral (stop). status() says what happened.
// Pure logic: told progress, positions and times, no clock; allocation only when a leg is built.
#pragma once

#include <string>
#include <vector>

#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>

#include "core/time.hpp"
#include "mission/mission.hpp"

namespace tiller::mission {

struct Leg {
  std::vector<MissionPoint> points;  // local NED m, the first where the leg starts
  std::vector<double> speeds;        // m/s per segment start (points.size() entries; 0: max)
};

class Sequencer {
 public:
  static constexpr std::size_t kMaxLegPoints = 1000;
  // A point this near the previous one replaces it: no zero-length segment, which the follower
  // would merge away (min_segment_length) and so shift the speeds' segment numbers.
  static constexpr double kSamePointM = 0.1;
  enum class Action { kNone, kNewLeg, kHold, kStop };
  enum class State { kIdle, kFlying, kLoitering, kHolding, kStopped, kFenceHold };

  explicit Sequencer(const Mission& m);

  // Builds the first leg from the vehicle's position: kNewLeg.
  Action begin(const MissionPoint& vehicle, TimeUs now);
  // The follower's progress on the current leg: complete.
  Action on_leg_complete(TimeUs now);
  // Every tick: a loiter that has lasted its time goes on.
  Action on_tick(TimeUs now);
  // The vehicle's position (checked odometry): the run-time fence.
  Action on_position(double north, double east, TimeUs now);

  const Leg& leg() const { return leg_; }
  int leg_number() const { return legs_; }  // legs built so far (the current is legs_ - 1)
  State state() const { return state_; }
  bool fence_breached() const { return breach_ >= 0; }
  const std::string& status() const { return status_; }

 private:
  Action build(const MissionPoint& from, TimeUs now);
  Action end_at_home(const MissionPoint& from, TimeUs now);
  MissionPoint home_from(const MissionPoint& p) const;

  const Mission& m_;
  std::vector<int> jumps_left_;
  std::size_t next_ = 0;  // the next item to take
  double speed_ = 0;
  Leg leg_;
  int legs_ = 0;
  State state_ = State::kIdle;
  State after_ = State::kHolding;  // what the current leg's completion leads to
  double loiter_s_ = 0;
  TimeUs loiter_until_ = -1;
  int breach_ = -1;
  std::string status_;
};

// A leg as the follower's messages: its points as `path`'s waypoints and its speeds as `speed`,
// both with `path_id` (utime left to the publisher). Reuses the messages' storage.
void leg_messages(const Leg& leg, std::int64_t path_id, path_t& path, path_speed_t& speed);

}  // namespace tiller::mission
