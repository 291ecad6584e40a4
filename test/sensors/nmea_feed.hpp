// Test helper: a receiver's NMEA 0183 stream (lib/sim/nmea.hpp's GGA, GSA, GSV, GST, RMC per
// epoch, with their checksums) made hostile epoch by epoch (a bad checksum, an impossible
// latitude, an RMC date jump, an outage), played through a REAL gpsd by gpsfake (Debian
// gpsd-clients) and read back by tiller-gnss's GpsdClient and GnssNode. Positions are WGS84
// degrees; epoch k is at 2026-12-01 12:00:00 UTC + k * period. The caller runs inside a private
// network namespace (tools/netns-run): gpsd listens on 127.0.0.1 only.
#pragma once

#include <string>
#include <vector>

#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/heartbeat_t.hpp>

#include "runtime/node.hpp"
#include "sensors/gnss_node.hpp"
#include "sim/nmea.hpp"

namespace tiller::sensors::test {

inline constexpr TimeUs kStartUtc = 1'796'126'400LL * kUsPerSecond;  // 2026-12-01 12:00:00 UTC

// One epoch of the stream: the receiver's fix and what goes wrong with it.
struct Epoch {
  sim::nmea::Fix fix;
  std::string latitude_text;  // when set, GGA's and RMC's latitude field (e.g. "9500.0000000")
  TimeUs rmc_date_shift = 0;  // us added to the time RMC's date is written from (a date jump)
  bool gst = true;            // false: this epoch's GST is not sent
  // Sentences sent with a bad checksum, by type ("GGA", "GSA", "GST", "RMC").
  std::vector<std::string> corrupt;
  // When set: a dual-antenna heading after RMC, "$GPHDT,<deg>,T" (or the text as given).
  std::string hdt;
};

// `n` epochs `period_s` apart from 12:00:00, moving north at 2 m/s from 59.437 N 10.6612 E
// (GeographicLib's geodesic), 9 satellites, HDOP 0.9, GST 1.5 / 1.2 / 2.8 m.
std::vector<Epoch> track(int n, double period_s);
// The stream's text (CR LF lines).
std::string text(const std::vector<Epoch>& epochs);

struct Capture : Bus {
  std::vector<gnss_fix_t> fixes;    // every TILLER_GNSS message
  std::vector<heading_t> headings;  // every TILLER_HEADING message
  heartbeat_t hb;                   // the last heartbeat
  void publish(std::string_view ch, const std::uint8_t* d, int n) override;
  // The fixes with a position and a receiver time.
  std::vector<gnss_fix_t> with_fix() const;
};

// Plays `epochs` through gpsfake (-c cycle_s between sentences) on `port` into `node`, whose
// outputs go to `out` (the node is ticked every 0.1 s of the wall clock). "" or why it failed.
std::string play(const std::vector<Epoch>& epochs, const std::string& port, double cycle_s,
                 GnssNode& node, Capture& out);

}  // namespace tiller::sensors::test
