// tiller-nav's logic, the estimator: TILLER_GNSS, TILLER_IMU, TILLER_HEADING and TILLER_PRESSURE
// in (and TILLER_DVL, an ROV's Doppler velocity log, with dvl.enabled), TILLER_ODOMETRY
// (odometry_t, local NED about the datum, body FRD velocity, covariances, validity bits) out at
// rate_hz, and TILLER_DATUM (datum_t: the frame's WGS84 origin) at the first tick with a datum and
// then every second. docs/navigation.md explains the filter (nav/ekf.hpp).
//
// GNSS fixes are converted to local NED about the datum (datum: first_fix: the mean of fixes that
// stayed consistent for datum_hold.hold_s, so a spurious first fix cannot set it, restarts
// counted in gnss.datum_restarts; or a configured one: the config, tiller-nav --datum or a
// mission's home, --datum-mission) with GeographicLib's LocalCartesian; a fix older than the
// filter's time is moved on to it with the estimated velocity (at most gnss.max_latency_s). Roll,
// pitch and body rates come from the IMU (its fused quaternion, else the accelerometer's tilt);
// heading from TILLER_HEADING (a magnetic one plus heading.declination_deg; a dual-antenna GNSS
// heading, source GNSS, is preferred while fresh: the others are then left out, counted in
// heading.other_ignored); depth from TILLER_PRESSURE, or 0 for a surface vehicle; the DVL's
// bottom-track velocity (body FRD over ground) with bottom lock and fom <= dvl.max_fom_mps, and
// without GNSS dead reckoning on it from north = east = 0, valid while a report was used within
// dvl.timeout_s (docs/navigation.md "ROVs: the DVL"); with sway.enabled the sway constraint at each
// tick while the IMU is fresh and the forward speed |u| >= sway.min_speed_mps (rejected.sway.gate
// counts the ones refused). The first measurement of each part sets it; later ones pass the
// innovation gate or are refused and counted (rejected.<input>.gate); a fix of an epoch already
// taken (the same gnss_utime) is refused and counted (rejected.gnss.repeated). A correction beyond
// the fix's own 1-sigma (the first fix after an outage, a reset) reaches the published position
// over time (recovery.rate_mps; counted in gnss.blended_corrections). `gnss.reset_after` refused
// fixes in a row reset the position to the fix (gnss.resets). Validity (odometry_t.valid): position
// while a fix was used and its largest 1-sigma is within limits.position_std_m; DEAD_RECKONING when
// no fix was used for gnss.timeout_s (the covariance grows); velocity within
// limits.velocity_std_mps; attitude while the IMU is fresh and the heading within
// limits.heading_std_deg; depth while a pressure sample is fresh (or a surface vehicle). Bad input
// (core/message_checks.hpp) is dropped and counted before it changes anything
// (rejected.<input>.invalid); stale or future by its utime: rejected.<input>.stale / .future. Time
// comes only from the executor: the filter runs on the times it is told.
#pragma once

#include <cstdint>
#include <string>

#include <GeographicLib/LocalCartesian.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/dvl_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/pressure_t.hpp>

#include "core/time.hpp"
#include "nav/ekf.hpp"
#include "nav/nav_params.hpp"
#include "runtime/node.hpp"

namespace tiller::nav {

class NavNode : public Node {
 public:
  explicit NavNode(const NavParams& p);

  void on_gnss(const gnss_fix_t& m, TimeUs now);
  void on_imu(const imu_t& m, TimeUs now);
  void on_heading(const heading_t& m, TimeUs now);
  void on_pressure(const pressure_t& m, TimeUs now);
  void on_dvl(const dvl_t& m, TimeUs now);

  const Ekf& filter() const { return ekf_; }
  const odometry_t& last_odometry() const { return odom_; }
  bool has_datum() const { return have_datum_; }
  // With the DVL as the position source: the heartbeat's status line (dead reckoning, its
  // 1-sigma and growth, or the loss), refreshed once a second.
  const std::string& dvl_status() const { return dvl_status_; }
  // The datum (WGS84 deg, m above the ellipsoid), once set.
  double datum_latitude() const { return datum_.LatitudeOrigin(); }
  double datum_longitude() const { return datum_.LongitudeOrigin(); }

 protected:
  void on_tick(TimeUs now) override;

 private:
  // Predicts the filter on to time t (no step back: an older t leaves it where it is).
  void advance(TimeUs t);
  // A measurement at its own time `utime` received at `now`: the filter moves on to it and the
  // result is its lag behind the filter's time (s, >= 0).
  double align(TimeUs utime, TimeUs now);
  // first_fix: holds fixes until they have been consistent for datum_hold.hold_s; true once the
  // datum is set (from this fix on, fixes are fused).
  bool hold_datum(const gnss_fix_t& m, double std_m, TimeUs taken);
  std::int32_t validity(TimeUs now) const;
  void fill(TimeUs now);
  void report(TimeUs now, std::int32_t valid);

  NavParams p_;
  Ekf ekf_;
  Motion motion_;
  double attitude_var_[2] = {0, 0};  // roll, pitch rad^2 (from the IMU)
  double rate_var_[3] = {0, 0, 0};   // p q r (rad/s)^2
  GeographicLib::LocalCartesian datum_;
  bool have_datum_ = false;
  TimeUs datum_sent_ = -1;  // TILLER_DATUM: at the first tick with a datum, then every second
  GeographicLib::LocalCartesian candidate_;  // the hold's first fix, its mean kept about it
  bool holding_ = false;
  TimeUs hold_since_ = 0;
  double hold_n_ = 0, hold_e_ = 0, hold_u_ = 0;  // sums of the held fixes, m about candidate_
  int held_ = 0;
  std::int64_t* datum_restarts_;
  // The published position is the filter's plus this offset (m, north and east): what is left of
  // a correction larger than the fix's 1-sigma, shrinking at recovery.rate_mps.
  double blend_n_ = 0, blend_e_ = 0;
  TimeUs blend_t_ = 0;
  std::int64_t* blended_;
  void blend(double n0, double e0, double std_m);       // after a fused fix moved (n0, e0)
  void fuse_velocity(const gnss_fix_t& m, double lag);  // speed and course over ground
  TimeUs last_gnss_heading_ = 0;  // receive time of the last dual-antenna GNSS heading
  bool have_gnss_heading_ = false;
  std::int64_t* heading_other_ignored_;
  TimeUs t_ = 0;  // the filter's time
  bool started_ = false;
  bool position_init_ = false, heading_init_ = false, depth_init_ = false;
  TimeUs last_fix_ = 0;       // receive time of the last fix used
  TimeUs last_imu_ = 0;       // ... of the last IMU sample
  TimeUs last_pressure_ = 0;  // ... of the last pressure sample
  bool have_imu_ = false, have_pressure_ = false;
  bool dead_reckoning_ = false;
  int gated_in_a_row_ = 0, heading_gated_in_a_row_ = 0, depth_gated_in_a_row_ = 0;
  Freshness gnss_fresh_, imu_fresh_, heading_fresh_, pressure_fresh_;
  odometry_t odom_{};
  std::int32_t reported_valid_ = -1;
  bool reported_dr_ = false;
  std::int64_t *bad_gnss_, *bad_imu_, *bad_heading_, *bad_pressure_;
  std::int64_t *gate_gnss_, *gate_gnss_velocity_, *gate_heading_, *gate_depth_, *gate_sway_;
  std::int64_t *fixes_used_, *no_fix_, *resets_, *too_late_, *dr_entered_, *invalid_out_;
  // The DVL (dvl.enabled): receive time of the last report used; dead reckoning on it alone
  // (no GNSS) started at the first one.
  Freshness dvl_fresh_;
  TimeUs last_dvl_ = 0;
  bool have_dvl_ = false, dvl_was_fresh_ = false;
  bool dvl_only_ = false;  // dvl.enabled and gnss.enabled false: the DVL is the position source
  int dvl_gated_in_a_row_ = 0;
  TimeUs dvl_status_at_ = -1;  // the dead-reckoning status line, refreshed once a second
  double dvl_std_then_ = 0;    // the position's 1-sigma at that time (m), for its growth rate
  std::string dvl_status_;
  bool dvl_fresh(TimeUs now) const;
  void report_dead_reckoning(TimeUs now, std::int32_t valid);
  std::int64_t *bad_dvl_, *dvl_no_lock_, *dvl_fom_, *gate_dvl_, *dvl_used_, *dvl_lost_;
  std::int64_t* repeated_;       // rejected.gnss.repeated: an epoch already fused
  std::int64_t last_epoch_ = 0;  // gnss_utime of the last fix taken
};

}  // namespace tiller::nav
