// tiller-gnss's logic: gpsd's reports (libgps gps_data_t, one per gps_read) -> gnss_fix_t on
// TILLER_GNSS, one message per TPV report that carries a mode, and one fix per epoch (a TPV whose
// fix time is the last published fix's is dropped and counted: reports.repeated_epoch).
//
// Mapping (gpsd client API, https://gpsd.gitlab.io/gpsd/libgps.html and gpsd_json(5)):
// fix.mode (MODE_NO_FIX / 2D / 3D) and fix.status (DGPS, RTK fixed/float, dead reckoning) ->
// fix_type; fix.latitude/longitude (deg), altHAE (ellipsoid, m), altMSL; speed (m/s), track
// (deg true -> rad in (-pi, pi]); satellites_used and dop.hdop from the last SKY; fix.time ->
// gnss_utime. Accuracy: when a GST report (the receiver's own 1-sigma errors, NMEA GST) for the
// same epoch has arrived, position_std = its lat/lon/alt deviations and accuracy_source =
// ACCURACY_RECEIVER; else gpsd's error model (epy, epx, epv: gpsd's estimates at 95 %
// confidence, divided by 2 here to approximate 1 sigma), ACCURACY_DOP; else 0, ACCURACY_NONE.
// gpsd's NaN (not known) becomes 0 with the matching flag, never NaN on the bus.
// Checks (issue 31; docs/sensors.md lists each with its threshold and why): a TPV with a fix but
// no latitude/longitude (gpsd's answer to a latitude of 95 deg) is dropped (rejected.fix.
// no_position); a 3D TPV without altitude is published as 2D. An epoch is published when it is
// whole: gpsd may report an epoch more than once (after a bad sentence it reports after GGA,
// before GST and RMC), so a fix that lacks what the receiver's last fix carried (velocity, the
// epoch's own GST, altitude) is held until a later report of the same epoch completes it, the
// next epoch begins, or epoch_wait passes (then published as it is: epochs.incomplete). A GST
// is used only for its own epoch (the same time to 1 ms). A fix that moved faster than
// max_speed_mps (plus jump_margin_m) since the last published one is dropped (rejected.fix.jump);
// a receiver time whose step differs from the host's by more than time_jump_s, or goes back, is
// dropped (rejected.fix.time_jump). accept_after consecutive such fixes consistent with each
// other are believed from then on (fix.jump_accepted / fix.time_jump_accepted): a receiver that
// was wrong before is not refused for ever. Each kind is said once on stderr.
// Dual-antenna heading (a u-blox moving-base pair, a Hemisphere or Septentrio compass): gpsd turns
// the receiver's NMEA HDT or THS (true heading) into an ATT report; its heading goes out as a
// heading_t on heading_channel (TILLER_HEADING), reference TRUE, source GNSS, variance
// heading_std^2, which tiller-nav prefers to a magnetic heading while it is fresh. A heading
// outside [0, 360) degrees or not finite is dropped (rejected.heading.range).
// Health: OK while fixes arrive; DEGRADED when gpsd says there is no fix or nothing came for
// `stale_after`; FAULT when the connection to gpsd is down (said by the glue, set_link()).
#pragma once

#include <cstdint>
#include <string>

#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>

#include "core/time.hpp"
#include "runtime/node.hpp"

struct gps_data_t;

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct GnssParams {
  std::string host = "127.0.0.1";  // gpsd's address
  std::string port = "2947";       // gpsd's port
  std::string channel = "TILLER_GNSS";
  TimeUs stale_after = 2 * kUsPerSecond;  // no fix for this long: DEGRADED
  TimeUs reconnect_period = kUsPerSecond;
  TimeUs epoch_wait = 500'000;  // us an incomplete epoch is held for the rest of its reports
  double max_speed_mps = 30;    // faster than any vehicle here (58 kn): a position jump
  double jump_margin_m = 25;    // receiver noise and multipath allowed on top of it
  double time_jump_s = 2.0;     // receiver time step - host time step beyond this: a time jump
  int accept_after = 5;         // consecutive consistent fixes at a new place / time: believed
  // Dual-antenna heading from gpsd's ATT reports (HDT/THS): published on heading_channel when
  // true ("" or false: not published).
  bool publish_heading = true;
  std::string heading_channel = "TILLER_HEADING";
  double heading_std =
      0.3 * 3.14159265358979323846 / 180;  // rad, 1-sigma (0.3 deg: a 1 m baseline)
};
GnssParams load_gnss_params(const config::Value& root);
GnssParams load_gnss_file(const std::string& path);

class GnssNode : public Node {
 public:
  explicit GnssNode(const GnssParams& p);
  // One report from gps_read() at time `now` (receive time).
  void on_gps(const gps_data_t& d, TimeUs now);
  // The glue's word on the connection to gpsd ("" = connected).
  void set_link(const std::string& problem, TimeUs now);
  const gnss_fix_t& last() const { return msg_; }
  const GnssParams& params() const { return p_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  // Where and when the last published fix was (the reference of the jump checks).
  struct Reference {
    bool set = false;
    std::int64_t gnss_utime = 0;
    TimeUs received = 0;
    double latitude = 0, longitude = 0;
  };
  enum class Jump { kNone, kPosition, kTime };
  Jump jump(const Reference& r, const gnss_fix_t& f) const;
  bool complete(const gnss_fix_t& f) const;
  void hold_or_publish(TimeUs now);
  void flush(TimeUs now);  // publishes the held epoch, if any, through the checks
  void accept(TimeUs now);
  void update_health(TimeUs now);
  std::string summary() const;  // the heartbeat's status while fixes arrive
  void say_once(int kind, const std::string& what);
  void on_attitude(const gps_data_t& d, TimeUs now);
  GnssParams p_;
  gnss_fix_t msg_{};
  heading_t heading_{};
  std::int64_t *headings_, *bad_heading_;
  std::string link_problem_ = "not connected to gpsd yet";
  TimeUs last_fix_ = INT64_MIN;
  bool last_had_fix_ = false;
  double gst_time_ = -1;  // s since the epoch of the last GST report
  double gst_std_[3] = {0, 0, 0};
  TimeUs last_gst_ = INT64_MIN;  // receive time of the last GST
  std::int64_t last_epoch_ = 0;  // gnss_utime of the last fix published
  bool held_ = false;            // msg_ is an epoch waiting for the rest of its reports
  TimeUs held_since_ = 0;
  bool expect_velocity_ = false, expect_3d_ = false;  // what the last published fix carried
  Reference ref_, candidate_;  // the last published fix; the last refused one
  int consistent_ = 0;         // refused fixes in a row consistent with each other
  unsigned said_ = 0;          // kinds said on stderr (bits)
  std::int64_t *fixes_, *no_fix_, *rejected_, *repeated_, *no_position_, *jump_, *time_jump_;
  std::int64_t *incomplete_, *jump_accepted_, *time_jump_accepted_;
};

}  // namespace tiller::sensors
