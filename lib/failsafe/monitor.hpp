// failsafe::Monitor: the failsafes that need sensors (docs/safety.md, "Failsafes"), as pure
// rules. Told readings and the time, it says which events hold, which were ever seen, the
// action in force and why; it reads no clock and allocates nothing after construction.
//
// Events (vehicle_status_t EVENT_*) and their rules, every threshold from FailsafeParams:
//   battery warn / critical  the bus voltage below the level for trigger_s without once rising
//                            above level + hysteresis_v (a sagging or noisy reading does not
//                            toggle); latched until a restart. Critical: its action, then a
//                            disarm disarm_after_s later.
//   leak                     a fresh leak_t with any probe wet for trigger_s; latched.
//   GNSS lost                lost_after_s since the last good fix (fix type >= min_fix,
//                            horizontal 1-sigma within max_std_m; with use_fix) or the last
//                            odometry with a valid position (with use_odometry), or since start
//                            when there was none; ends after recover_s of good input (each within
//                            stale_s of the one before) without a break.
//   geofence                 event: the vehicle within margin_m of the polygon's edge or outside.
//                            Action (latched until the operator's next START / RESUME): the
//                            vehicle moves outward (faster than kMinOutwardSpeed across the
//                            nearest edge) and its position lookahead_s ahead is within margin_m
//                            of the edge or outside.
//   depth limit              deeper than limit_m; ends above limit_m - hysteresis_m. Action:
//                            RISE (up-thrust) while it holds. A depth the odometry flags invalid
//                            (VALID_DEPTH clear) is no reading, as stale odometry: the rule keeps
//                            its last verdict (a rise goes on: the vehicle was too deep when the
//                            depth was last known, and up is the safe way; none starts on it),
//                            and depth_known() says so (the node counts and reports it).
// Frames and units: positions local NED (m), velocity NED (m/s), depth down (m), volts, seconds
// as TimeUs. The action in force is the most severe of the events' actions, in the order
// NONE < WARN < HOLD < NEUTRAL < RISE < SURFACE < DISARM.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/time.hpp"

namespace tiller::failsafe {

// Values equal vehicle_status_t ACTION_* (checked in monitor.cpp).
enum class Action : std::int8_t {
  kNone = 0,
  kWarn = 1,
  kHold = 2,
  kReturn = 3,  // in the message for later; no rule gives it yet
  kSurface = 4,
  kNeutral = 5,
  kDisarm = 6,
  kRise = 7,
};
// Event bits (vehicle_status_t EVENT_*).
inline constexpr std::int32_t kBatteryWarn = 1, kBatteryCritical = 2, kLeak = 4, kGnssLost = 8,
                              kGeofence = 16, kDepthLimit = 32;

struct BatteryParams {
  bool enabled = false;
  double warn_v = 0;           // V: below it: warn
  double critical_v = 0;       // V: below it: critical_action, then disarm
  double hysteresis_v = 0.2;   // V: the timer restarts only above level + this
  TimeUs trigger = 2'000'000;  // below for this long
  Action critical_action = Action::kHold;
  TimeUs disarm_after = 60'000'000;  // after critical; < 0: never
  TimeUs stale = 2'000'000;          // power_t older than this: no reading (reported, no action)
  // The pack's internal resistance (ohm): > 0 compares the sag-compensated (resting) voltage
  // V + I R instead of the bus voltage V, so a burst of full thrust is not a low battery (as
  // ArduPilot's BATT_FS_VOLTSRC = 1). 0: the bus voltage as read. Used by FailsafeNode.
  double resistance_ohm = 0;
};
struct LeakParams {
  bool enabled = false;
  Action action = Action::kSurface;
  TimeUs trigger = 0;        // wet for this long
  TimeUs disarm_after = -1;  // after the leak (surface, hold): disarm; < 0: never
  TimeUs stale = 2'000'000;
};
struct GnssParams {
  bool enabled = false;
  TimeUs lost_after = 5'000'000;
  TimeUs recover = 2'000'000;
  std::int8_t min_fix = 1;    // gnss_fix_t FIX_* (FIX_DEAD_RECKONING never counts)
  double max_std_m = 0;       // horizontal 1-sigma above this is not good; 0: not checked
  TimeUs stale = 1'000'000;   // a fix or odometry older than this is not good
  bool use_fix = true;        // TILLER_GNSS must have a good fix
  bool use_odometry = false;  // TILLER_ODOMETRY must be fresh with a valid position
  Action action = Action::kHold;
};
struct Point {
  double north = 0, east = 0;  // m, local NED
};
struct GeofenceParams {
  bool enabled = false;
  std::vector<Point> polygon;  // >= 3 vertices, simple (not self-intersecting), either winding
  double margin_m = 1.0;
  double lookahead_s = 2.0;
  Action action = Action::kHold;
};
struct DepthParams {
  bool enabled = false;
  double limit_m = 0;  // m down
  double hysteresis_m = 0.5;
};

struct MonitorParams {
  BatteryParams battery;
  LeakParams leak;
  GnssParams gnss;
  GeofenceParams geofence;
  DepthParams depth;
  TimeUs odometry_stale = 1'000'000;  // older odometry: geofence and depth keep their last verdict
};

struct Status {
  std::int32_t active = 0;   // EVENT_* bits holding now
  std::int32_t latched = 0;  // EVENT_* bits seen since start (a superset of active)
  Action action = Action::kNone;
  const char* reason = "";  // of the most severe event; points into the monitor (stable until the
                            // next step)
  bool changed = false;     // active, latched, action or reason differ from the last step
};

// Signed distance (m) from p to the polygon's boundary: + inside, - outside; and the unit
// outward normal of the nearest edge (n_north, n_east). Pure geometry, no allocation.
double signed_distance(const std::vector<Point>& polygon, Point p, double* n_north = nullptr,
                       double* n_east = nullptr);
// The speed that counts as moving toward the fence (m/s).
inline constexpr double kMinOutwardSpeed = 0.05;

class Monitor {
 public:
  explicit Monitor(const MonitorParams& p);

  void on_power(double voltage, TimeUs now);
  void on_leak(bool any_wet, TimeUs now);
  // A fix: good (fix type, accuracy) as gnss_good() says.
  void on_gnss(std::int8_t fix_type, double horizontal_std_m, TimeUs now);
  // Odometry: position (n, e, d) m NED, velocity over ground (vn, ve) m/s NED, and whether its
  // position and its depth are valid (the estimator's flags; the simulator's are always valid).
  // An invalid depth is not taken (the depth rule keeps its verdict).
  void on_odometry(double n, double e, double d, double vn, double ve, bool position_valid,
                   bool depth_valid, TimeUs now);
  // The operator's START or RESUME: ends a geofence action (it comes back at once if the
  // vehicle still moves outward near the edge).
  void on_operator_go(TimeUs now);
  const Status& step(TimeUs now);
  const Status& status() const { return status_; }
  // Whether a fix is good by the GNSS rule.
  bool gnss_good(std::int8_t fix_type, double horizontal_std_m) const;
  const MonitorParams& params() const { return p_; }
  double distance_to_fence() const { return fence_d_; }  // m, + inside (when known)
  // False while the latest odometry's depth is invalid (the depth rule cannot judge).
  bool depth_known() const { return depth_valid_; }
  bool position_known() const { return position_valid_; }

 private:
  struct Below {  // a level with hysteresis and a trigger time
    bool below = false;
    TimeUs since = 0;
  };
  void update_below(Below& b, double v, double level, TimeUs now);

  MonitorParams p_;
  Status status_;
  TimeUs start_ = -1;
  // Battery.
  bool have_power_ = false;
  TimeUs power_at_ = 0;
  double voltage_ = 0;
  Below warn_, critical_;
  TimeUs critical_at_ = -1, warn_at_ = -1;
  double critical_voltage_ = 0, warn_voltage_ = 0;  // when each latched
  // Leak.
  bool have_leak_ = false;
  TimeUs leak_at_ = 0;
  bool wet_ = false;
  TimeUs wet_since_ = 0;
  TimeUs leak_latched_at_ = -1;
  // GNSS.
  TimeUs fix_good_at_ = -1;    // last good fix
  TimeUs odom_valid_at_ = -1;  // last odometry with a valid position
  TimeUs good_since_ = -1;     // start of the current unbroken run of good input (-1: bad now)
  bool gnss_lost_ = false;
  // Odometry (geofence, depth).
  bool have_odom_ = false;
  TimeUs odom_at_ = 0;
  double n_ = 0, e_ = 0, d_ = 0, vn_ = 0, ve_ = 0;
  double fence_d_ = 0;
  bool fence_hold_ = false;
  bool near_fence_ = false;
  bool deep_ = false;
  bool depth_valid_ = false;     // the latest odometry's VALID_DEPTH; d_ is the last valid depth
  bool position_valid_ = false;  // its VALID_POSITION; n_, e_, vn_, ve_ are the last valid ones
  char reason_[128] = {};
  char last_reason_[128] = {};
};

}  // namespace tiller::failsafe
