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
// Health: OK while fixes arrive; DEGRADED when gpsd says there is no fix or nothing came for
// `stale_after`; FAULT when the connection to gpsd is down (said by the glue, set_link()).
#pragma once

#include <cstdint>
#include <string>

#include <tiller/gnss_fix_t.hpp>

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

 protected:
  void on_tick(TimeUs now) override;

 private:
  GnssParams p_;
  gnss_fix_t msg_{};
  std::string link_problem_ = "not connected to gpsd yet";
  TimeUs last_fix_ = INT64_MIN;
  bool last_had_fix_ = false;
  double gst_time_ = -1;  // s since the epoch of the last GST report
  double gst_std_[3] = {0, 0, 0};
  std::int64_t last_epoch_ = 0;  // gnss_utime of the last fix published
  std::int64_t *fixes_, *no_fix_, *rejected_, *repeated_;
};

}  // namespace tiller::sensors
