// tiller-failsafe's logic: the failsafes that need sensors (failsafe/monitor.hpp) as a node.
//
// Subscribes TILLER_POWER (power_t), TILLER_LEAK (leak_t), TILLER_GNSS (gnss_fix_t),
// TILLER_ODOMETRY (position, depth, velocity) and TILLER_MISSION_COMMAND (an operator's START or
// RESUME, a new command_id, ends a geofence hold). Every tick (rate_hz) it publishes
// TILLER_VEHICLE_STATUS (events active and latched, the action in force, the reason) and
// TILLER_WRENCH_FAILSAFE (wrench_t SOURCE_FAILSAFE, body FRD: valid only for SURFACE, [0 0
// -surface_thrust_n 0 0 0] N (zero once shallower than surface_depth_m), RISE, [0 0 -rise_thrust_n
// 0 0 0], and NEUTRAL, zero; the mixer then allocates it instead of every other source). HOLD
// reaches the thrusters through the arbiter (tiller-velocity-pid reads TILLER_VEHICLE_STATUS) and
// station keeping. When the action is DISARM it publishes a disarm request on TILLER_ARM_REQUEST at
// once and again every second (tiller-esc always takes a disarm). The heartbeat says the reason
// (DEGRADED while an event holds, and while an enabled rule's sensor is silent) and counts each
// event's latchings
// ("event.<name>"). Bad input (core/message_checks.hpp) is dropped and counted
// (rejected.power.invalid, rejected.leak.invalid, rejected.gnss.invalid,
// rejected.odometry.invalid, rejected.mission_command.invalid); an input older than its limit
// by its utime is refused (rejected.<input>.stale / .future). A well-formed odometry whose depth
// is flagged invalid is no depth reading: the depth rule keeps its last verdict (monitor.hpp),
// the message counted in odometry.depth_invalid, the heartbeat DEGRADED while it lasts.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <tiller/gnss_fix_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/wrench_t.hpp>

#include "failsafe/failsafe_config.hpp"
#include "failsafe/monitor.hpp"
#include "runtime/node.hpp"

namespace tiller::failsafe {

class FailsafeNode : public Node {
 public:
  explicit FailsafeNode(const FailsafeNodeParams& p);

  void on_power(const power_t& m, TimeUs now);
  void on_leak(const leak_t& m, TimeUs now);
  void on_gnss(const gnss_fix_t& m, TimeUs now);
  void on_odometry(const odometry_t& m, TimeUs now);
  void on_mission_command(const mission_command_t& m, TimeUs now);
  void on_tick(TimeUs now) override;

  const Monitor& monitor() const { return monitor_; }
  const vehicle_status_t& last_status() const { return status_; }

 private:
  void update_health(TimeUs now);

  FailsafeNodeParams p_;
  Monitor monitor_;
  vehicle_status_t status_{};
  wrench_t wrench_{};
  TimeUs disarm_sent_at_ = -1;
  std::int32_t counted_ = 0;  // latched bits already counted in event.*
  std::array<std::int64_t, 8> seen_ids_{};
  std::size_t next_id_ = 0;
  TimeUs power_at_ = -1, leak_at_ = -1, gnss_at_ = -1, odom_at_ = -1;
  double depth_ = 0;          // m down, from the last odometry
  bool depth_valid_ = false;  // its VALID_DEPTH bit (without it: surfacing keeps its up-thrust)
  std::string health_text_;
  std::int8_t health_ = -1;
  std::int64_t *bad_power_, *bad_leak_, *bad_gnss_, *bad_odometry_, *bad_command_;
  std::int64_t* disarm_requests_;
  std::int64_t* depth_invalid_;     // odometry.depth_invalid: messages whose depth the rule skips
  std::int64_t* position_invalid_;  // odometry.position_invalid: the geofence skips their position
  std::array<std::int64_t*, 6> event_counters_{};
};

}  // namespace tiller::failsafe
