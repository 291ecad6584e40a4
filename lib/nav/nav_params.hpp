// tiller-nav's settings (config/nav/*.yaml) and their strict loader. Units: SI, angles in
// radians (config keys ending in _deg are read as degrees); docs/navigation.md explains each.
#pragma once

#include <string>

#include "nav/ekf.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::nav {

enum class DepthSource { kSurface, kPressure };

struct NavParams {
  double rate_hz = 50;  // odometry rate (the node's tick)
  DepthSource depth_source = DepthSource::kSurface;
  // Datum of local NED: the first fix used, or a fixed one (WGS84 deg, m above the ellipsoid).
  bool fixed_datum = false;
  double datum_latitude_deg = 0, datum_longitude_deg = 0, datum_altitude_m = 0;
  // first_fix: the datum is set only once fixes have stayed consistent for hold_s: each within
  // max(consistent_m, 3 x its own largest 1-sigma) of the held fixes' mean; a fix outside starts
  // the hold over from it (a spurious first fix cannot set the datum). Until then no fix is
  // fused: the position is invalid. The datum is the held fixes' mean. 0 s: the first fix.
  struct DatumHold {
    double hold_s = 5.0;
    double consistent_m = 5.0;
  } datum_hold;
  // Back to the receiver smoothly: a fix that moves the filter's position by more than the fix's
  // own largest 1-sigma (the first fix after a GNSS outage, a reset) moves the published position
  // by that 1-sigma at once; the rest is an offset that shrinks at rate_mps (its square added to
  // the published position variance), so no consumer sees a jump larger than the receiver's
  // error or a setpoint step. rate_mps 0: the old jump.
  struct Recovery {
    double rate_mps = 0.5;
  } recovery;

  struct Gnss {
    bool enabled = true;         // false: no position source (position never valid)
    int min_fix = 1;             // gnss_fix_t::FIX_2D or FIX_3D: the least fix type used
    double default_std_m = 2.5;  // 1-sigma per horizontal axis when a fix says none
    double min_std_m = 0.3;      // floor on a fix's own sigma
    // An RTK fix whose accuracy is not the receiver's own (gpsd's DOP model, or none): at most
    // this 1-sigma per horizontal axis, m (then the floor above). docs/sensors.md.
    double rtk_fixed_std_m = 0.05;
    double rtk_float_std_m = 0.5;
    bool use_velocity = true;  // speed and course over ground as a velocity measurement
    double velocity_std_mps = 0.1;
    double gate_chi2 = 13.8;     // NIS gate, 2 degrees of freedom (13.8: 1 in 1000)
    int reset_after = 25;        // consecutive gated fixes, then the position is reset
    double timeout_s = 1.0;      // no fix used for this long: dead reckoning
    double max_latency_s = 0.5;  // a fix older than the filter's time by more is refused
    double latency_s = 0;        // the fix was taken this long before its utime (receiver delay)
  } gnss;
  struct Heading {
    double declination = 0;      // rad, added to a magnetic heading (east positive)
    double default_std = 0.035;  // rad, when the message says none
    double gate_chi2 = 10.8;     // 1 degree of freedom, 1 in 1000
    int reset_after = 25;        // consecutive gated headings, then the heading is reset
  } heading;
  struct Imu {
    double timeout_s = 0.5;                // attitude invalid past this without an IMU sample
    double default_attitude_std = 0.0175;  // rad, roll and pitch, when the IMU says none
    double default_rate_std = 0.01;        // rad/s, when the IMU says none
    bool use_acceleration = false;         // the accelerometer drives u and v (an aided INS)
  } imu;
  struct Depth {
    double default_std_m = 0.05;  // when the pressure message says none
    double gate_chi2 = 10.8;
    double timeout_s = 1.0;  // depth invalid past this without a pressure sample
    int reset_after = 25;    // consecutive gated samples, then the depth is reset to one
  } depth;
  // A Doppler velocity log (TILLER_DVL, dvl_t): an ROV's velocity over ground in body FRD.
  // A report is used with bottom lock and its fom at most max_fom_mps; its covariance (or fom^2
  // on the diagonal when it has none), each variance floored at min_std_mps^2. The DVL sits at
  // lever_arm_m from the body origin (FRD, m): it sees v + omega x r, so omega x r is taken off.
  // Without a position source (gnss.enabled false) the first report used starts dead reckoning
  // at north = east = 0 with initial_position_std_m (the local frame: where the dive began);
  // the position's covariance then grows with the velocity's. Position and velocity are valid
  // only while a report was used within timeout_s (a lost bottom lock or a stopped driver makes
  // them invalid at once: position hold falls back, control/rov_node.hpp).
  struct Dvl {
    bool enabled = false;
    double max_fom_mps = 0.05;
    double min_std_mps = 0.002;
    double lever_arm_m[3] = {0, 0, 0};
    double timeout_s = 1.0;
    double gate_chi2 = 16.3;  // 3 degrees of freedom, 1 in 1000
    int reset_after = 10;     // consecutive gated reports, then the velocity is reset to one
    double initial_position_std_m = 0.01;
  } dvl;
  // The sway constraint (Ekf::update_sway): a surface vessel's sway through the water is near 0,
  // applied at each tick while the IMU is fresh and |u| >= min_speed_mps. Off by default: an ROV
  // translates sideways on purpose; and at rest or holding station the current may push a hull
  // sideways.
  struct Sway {
    bool enabled = false;
    double std_mps = 0.02;       // m/s, 1-sigma on a straight
    double rate_gain_s = 0.5;    // s: + rate_gain_s |r| |u| (m/s) in a turn (r rad/s, u m/s)
    double min_speed_mps = 0.3;  // applied only above this forward speed (m/s, |u|)
    double gate_chi2 = 10.8;     // 1 degree of freedom, 1 in 1000
  } sway;
  ProcessNoise process;
  double initial_velocity_std_mps = 2.0;
  double initial_current_std_mps = 0.3;  // m/s, north and east each
  double initial_gyro_bias_std = 0.02;   // rad/s
  double initial_accel_bias_std = 0.1;   // m/s^2
  struct Limits {                        // past these 1-sigma values the part is flagged invalid
    double position_std_m = 10;
    double velocity_std_mps = 0.5;
    double heading_std = 0.175;  // rad
    double depth_std_m = 0.5;
  } limits;
};

// Strict loader: every error names the file, the key and what was expected.
NavParams load_nav_params(const config::Value& root);
NavParams load_nav_file(const std::string& path);

}  // namespace tiller::nav
