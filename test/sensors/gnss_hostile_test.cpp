// Issue 31: hostile and realistic NMEA through a REAL gpsd (gpsfake, Debian gpsd-clients) into
// tiller-gnss's GnssNode, one case per defect the issue reports; each failed on the code before
// the fix (figures in the comments). A 5 Hz receiver moving north at 2 m/s (nmea_feed.hpp), 30
// epochs per case (6 s); gpsd needs the first few to find the device, so checks start at epoch 5.
#include <gtest/gtest.h>

#include <gps.h>
#include <GeographicLib/Geodesic.hpp>

#include <cmath>
#include <cstdio>

#include "nav/nav_node.hpp"
#include "nmea_feed.hpp"

namespace tiller::sensors {
namespace {

using test::Capture;
using test::Epoch;
using test::kStartUtc;

constexpr double kPeriod = 0.2;         // s, 5 Hz
constexpr double kCycle = kPeriod / 7;  // s between sentences: 7 per epoch (3 GSV)
constexpr int kFirstChecked = 5;

int epoch_of(const gnss_fix_t& f) {
  return static_cast<int>(
      std::lround(static_cast<double>(f.gnss_utime - kStartUtc) / 1e6 / kPeriod));
}
// Distance (m) from a fix to where the track is at that fix's epoch.
double off_track(const gnss_fix_t& f, const std::vector<Epoch>& track) {
  const int k = epoch_of(f);
  if (k < 0 || k >= static_cast<int>(track.size())) return 1e9;
  double s = 0;
  GeographicLib::Geodesic::WGS84().Inverse(f.latitude, f.longitude, track[k].fix.latitude_deg,
                                           track[k].fix.longitude_deg, s);
  return s;
}

GnssParams params(const char* port) {
  GnssParams p;
  p.port = port;
  return p;
}

// Case 1. Before: a latitude of 95 deg (gpsd: a 3D TPV without lat/lon) was published as a fix at
// 0 N 0 E; a 1 km jump in 0.2 s (5 km/s) was published. After: both dropped and counted; a
// receiver that stays at the new place is believed after accept_after fixes.
TEST(GnssHostile, ImpossiblePositionsAreDroppedAndCounted) {
  std::vector<Epoch> e = test::track(40, kPeriod);
  e[12].latitude_text = "9500.0000000";
  e[18].fix.latitude_deg += 0.009;  // 1.0 km north, one epoch
  GnssParams p = params("29481");
  GnssNode node(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, node, out), "");
  int zero = 0, far = 0, n = 0;
  bool seen[40] = {};
  for (const auto& f : out.with_fix()) {
    const int k = epoch_of(f);
    if (k < kFirstChecked) continue;
    ++n;
    if (k >= 0 && k < 40) seen[k] = true;
    zero += std::fabs(f.latitude) < 1 && std::fabs(f.longitude) < 1;
    far += off_track(f, e) > 0.01;
  }
  std::printf(
      "%d fixes; at 0,0: %d; off the track: %d; rejected.fix.no_position %lld, .jump %lld\n", n,
      zero, far, static_cast<long long>(node.counter_value("rejected.fix.no_position")),
      static_cast<long long>(node.counter_value("rejected.fix.jump")));
  EXPECT_GE(n, 25);
  EXPECT_EQ(zero, 0);
  EXPECT_EQ(far, 0);
  EXPECT_FALSE(seen[12]);
  EXPECT_FALSE(seen[18]);
  EXPECT_TRUE(seen[11] && seen[13] && seen[17] && seen[19]);
  EXPECT_EQ(node.counter_value("rejected.fix.no_position"), 1);
  EXPECT_EQ(node.counter_value("rejected.fix.jump"), 1);
  EXPECT_GE(out.hb.rejected, 2);
}

TEST(GnssHostile, AReceiverThatStaysAtANewPlaceIsBelievedAfterAcceptAfterFixes) {
  std::vector<Epoch> e = test::track(40, kPeriod);
  for (int k = 15; k < 40; ++k) e[k].fix.latitude_deg += 0.009;  // 1 km north from epoch 15 on
  GnssParams p = params("29482");
  GnssNode node(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, node, out), "");
  int first_after = -1;
  for (const auto& f : out.with_fix())
    if (first_after < 0 && epoch_of(f) >= 15) first_after = epoch_of(f);
  EXPECT_EQ(first_after, 15 + p.accept_after);
  EXPECT_EQ(node.counter_value("rejected.fix.jump"), p.accept_after);
  EXPECT_EQ(node.counter_value("fix.jump_accepted"), 1);
}

// Case 2. Before: one RMC with a bad checksum made gpsd report each later epoch after its GGA
// (before GST and RMC): every later fix went without velocity and with the last epoch's GST
// (24 of 24 epochs after it). After: an epoch is published when gpsd's reports of it are whole;
// the bad sentence costs at most its own epoch's velocity. A bad GGA costs that epoch's altitude.
TEST(GnssHostile, OneBadChecksumCostsAtMostThatSentence) {
  std::vector<Epoch> e = test::track(30, kPeriod);
  e[10].corrupt = {"RMC"};
  e[20].corrupt = {"GGA"};
  GnssParams p = params("29483");
  GnssNode node(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, node, out), "");
  int n = 0, no_velocity = 0, stale_accuracy = 0, no_altitude = 0;
  for (const auto& f : out.with_fix()) {
    const int k = epoch_of(f);
    if (k < kFirstChecked) continue;
    ++n;
    no_velocity += !f.velocity_valid;
    stale_accuracy += f.accuracy_source != gnss_fix_t::ACCURACY_RECEIVER;
    if (f.fix_type >= gnss_fix_t::FIX_3D) {
      EXPECT_NEAR(f.altitude, 12.3 + 39.8, 1e-3) << "epoch " << k;
    } else {
      ++no_altitude;
      EXPECT_EQ(k, 20) << "a 2D fix";
    }
    if (k != 10) {
      EXPECT_TRUE(f.velocity_valid) << "epoch " << k;
      EXPECT_NEAR(f.speed, 2.0, 1e-3) << "epoch " << k;
    }
  }
  std::printf("%d fixes; without velocity %d, without the receiver's accuracy %d, 2D %d\n", n,
              no_velocity, stale_accuracy, no_altitude);
  EXPECT_GE(n, 20);
  EXPECT_LE(no_velocity, 1);
  EXPECT_EQ(stale_accuracy, 0);
  EXPECT_LE(no_altitude, 1);
}

// Case 3. Before: while gpsd reports an epoch before its GST (its first epochs, and after an
// outage), the fix took the previous epoch's GST. After: each fix carries its own epoch's GST
// (here 1.0 + 0.05 k m north, 0.8 + 0.05 k m east), also the first one after a 1.2 s outage.
TEST(GnssHostile, TheAccuracyIsTheCurrentEpochs) {
  std::vector<Epoch> e = test::track(36, kPeriod);
  for (int k = 0; k < 36; ++k) {
    e[k].fix.std_north_m = 1.0 + 0.05 * k;
    e[k].fix.std_east_m = 0.8 + 0.05 * k;
  }
  for (int k = 14; k < 20; ++k) e[k].fix.valid = false;  // an outage: no fix for 1.2 s
  GnssParams p = params("29484");
  GnssNode node(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, node, out), "");
  int n = 0, wrong = 0, first_after = -1;
  for (const auto& f : out.with_fix()) {
    const int k = epoch_of(f);
    if (k < kFirstChecked) continue;
    ++n;
    if (first_after < 0 && k >= 20) {
      first_after = k;
      EXPECT_EQ(f.accuracy_source, gnss_fix_t::ACCURACY_RECEIVER);
    }
    const bool right = f.accuracy_source == gnss_fix_t::ACCURACY_RECEIVER &&
                       std::fabs(f.position_std[0] - (1.0 + 0.05 * k)) < 1e-3 &&
                       std::fabs(f.position_std[1] - (0.8 + 0.05 * k)) < 1e-3;
    wrong += !right;
    EXPECT_TRUE(right) << "epoch " << k << ": " << f.position_std[0] << " source "
                       << int(f.accuracy_source);
  }
  std::printf("%d fixes, %d with another epoch's or no accuracy; first after the outage: %d\n", n,
              wrong, first_after);
  EXPECT_GE(n, 20);
  EXPECT_EQ(first_after, 20);
}

// Case 4. Before: an RMC dated a year later (gpsd: that epoch's TPV in 2027) was published.
// After: a receiver time that jumps against the host's clock is dropped and counted; a receiver
// whose time really changed (the date from epoch 24 on is a day later) is believed after
// accept_after fixes.
TEST(GnssHostile, TimeJumpsAreDroppedAndCounted) {
  std::vector<Epoch> e = test::track(40, kPeriod);
  e[12].rmc_date_shift = 365LL * 86400 * kUsPerSecond;
  for (int k = 24; k < 40; ++k) e[k].rmc_date_shift = 86400LL * kUsPerSecond;
  GnssParams p = params("29485");
  GnssNode node(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, node, out), "");
  int n = 0, year = 0, first_day = -1;
  for (const auto& f : out.with_fix()) {
    const double dt = static_cast<double>(f.gnss_utime - kStartUtc) / 1e6;
    if (dt > 300 * 86400) ++year;
    if (dt > 86000 && first_day < 0)
      first_day = static_cast<int>(std::lround((dt - 86400) / kPeriod));
    ++n;
  }
  std::printf(
      "%d fixes; a year later: %d; the day after from epoch %d; rejected.fix.time_jump %lld\n", n,
      year, first_day, static_cast<long long>(node.counter_value("rejected.fix.time_jump")));
  EXPECT_EQ(year, 0);
  EXPECT_GE(node.counter_value("rejected.fix.time_jump"), 1 + p.accept_after);
  // gpsd takes the date from RMC, the epoch's last sentence: epoch 24's TPV is still dated the
  // day before (its GGA set it), epoch 25's the day after.
  EXPECT_GE(first_day, 25 + p.accept_after - 1);
  EXPECT_LE(first_day, 25 + p.accept_after + 1);
  EXPECT_EQ(node.counter_value("fix.time_jump_accepted"), 1);
}

// Case 5. Before: tiller-nav's datum was the first fix it used, so a receiver's spurious first
// fixes (here 20 m east for the first 8 epochs, 1.6 s, as multipath at a quay gives) set the
// local frame 20 m off. After: the datum waits for fixes consistent for datum_hold.hold_s (2 s
// here): the spurious ones restart the hold, and the datum is the mean of the good ones.
TEST(GnssHostile, ASpuriousFirstFixCannotSetTheDatum) {
  std::vector<Epoch> e = test::track(40, kPeriod);
  const double spurious_deg = 20.0 / (111'320.0 * std::cos(e[0].fix.latitude_deg * M_PI / 180));
  for (int k = 0; k < 8; ++k) e[k].fix.longitude_deg += spurious_deg;
  GnssParams p = params("29486");
  GnssNode gnss(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, gnss, out), "");
  nav::NavParams np;
  np.datum_hold.hold_s = 2.0;
  np.datum_hold.consistent_m = 5.0;
  nav::NavNode nav(np);
  int first = -1, datum_epoch = -1, from_datum = 0;
  for (const auto& f : out.with_fix()) {
    if (first < 0) first = epoch_of(f);
    nav.on_gnss(f, f.utime);
    if (datum_epoch < 0 && nav.has_datum()) datum_epoch = epoch_of(f);
    from_datum += nav.has_datum();
  }
  ASSERT_GE(first, 0);
  ASSERT_LT(first, 8) << "the test needs spurious fixes to reach the estimator";
  ASSERT_TRUE(nav.has_datum());
  // The good fixes held: from epoch 8 to the one 2 s later; the datum is their mean.
  EXPECT_EQ(datum_epoch, 8 + 10);
  double lat = 0, lon = 0;
  for (int k = 8; k <= datum_epoch; ++k) {
    lat += e[k].fix.latitude_deg;
    lon += e[k].fix.longitude_deg;
  }
  lat /= datum_epoch - 8 + 1;
  lon /= datum_epoch - 8 + 1;
  double to_good = 0, to_spurious = 0;
  const auto& g = GeographicLib::Geodesic::WGS84();
  g.Inverse(nav.datum_latitude(), nav.datum_longitude(), lat, lon, to_good);
  g.Inverse(nav.datum_latitude(), nav.datum_longitude(), e[first].fix.latitude_deg,
            e[first].fix.longitude_deg, to_spurious);
  std::printf(
      "datum set at epoch %d: %.3f m from the good fixes' mean, %.1f m from the first "
      "(spurious) fix; gnss.datum_restarts %lld\n",
      datum_epoch, to_good, to_spurious,
      static_cast<long long>(nav.counter_value("gnss.datum_restarts")));
  EXPECT_LT(to_good, 0.05);
  EXPECT_GT(to_spurious, 15.0);
  EXPECT_EQ(nav.counter_value("gnss.datum_restarts"), 1);
  EXPECT_EQ(nav.counter_value("gnss.fixes_used"), from_datum) << "fused from the datum's on";
}

// Dual-antenna heading (issue 31, "what real boats carry"): a receiver's NMEA HDT through the real
// gpsd (its ATT report) becomes a true GNSS heading on TILLER_HEADING; an impossible one (400
// deg) is dropped and counted. tiller-nav then takes it in preference to the IMU's magnetic
// heading (which here is 30 deg off, as a compass near a steel hull can be). gpsd 3.22 writes
// every ATT after the first with a malformed time field; GpsdClient reads its heading anyway.
TEST(GnssHostile, ADualAntennaHeadingIsTheHeadingSource) {
  std::vector<Epoch> e = test::track(30, kPeriod);
  for (int k = 0; k < 30; ++k) {
    char b[16];
    std::snprintf(b, sizeof b, "%.2f", 10.0 + 0.5 * k);
    e[k].hdt = b;
  }
  e[15].hdt = "400.00";
  GnssParams p = params("29487");
  GnssNode gnss(p);
  Capture out;
  ASSERT_EQ(test::play(e, p.port, kCycle, gnss, out), "");
  ASSERT_GE(out.headings.size(), 20u);
  for (const auto& h : out.headings) {
    EXPECT_EQ(h.reference, heading_t::REFERENCE_TRUE);
    EXPECT_EQ(h.source, heading_t::SOURCE_GNSS);
    EXPECT_NEAR(h.variance, std::pow(0.3 * M_PI / 180, 2), 1e-12);
    const double k = (h.heading * 180 / M_PI - 10.0) / 0.5;  // which epoch's heading it is
    EXPECT_NEAR(k, std::round(k), 1e-6) << h.heading;
    EXPECT_NE(std::lround(k), 15);
  }
  // gpsd itself drops the 400 deg HDT; a report that still carried one (another gpsd, a UBX
  // path) is dropped here and counted.
  gps_data_t bad{};
  bad.set = ATTITUDE_SET;
  bad.attitude.heading = 400.0;
  gnss.on_gps(bad, out.headings.back().utime + 1);
  bad.attitude.heading = std::nan("");
  gnss.on_gps(bad, out.headings.back().utime + 2);
  EXPECT_EQ(gnss.counter_value("rejected.heading.range"), 2);
  // The estimator: GNSS headings and, in between, magnetic ones 30 deg off.
  nav::NavParams np;
  np.datum_hold.hold_s = 0;
  nav::NavNode nav(np);
  const heading_t& last = out.headings.back();
  for (const auto& h : out.headings) {
    nav.on_heading(h, h.utime);
    heading_t mag = h;
    mag.utime = h.utime + 50'000;
    mag.heading = h.heading + 30 * M_PI / 180;
    mag.reference = heading_t::REFERENCE_MAGNETIC;
    mag.source = heading_t::SOURCE_AHRS;
    mag.variance = 0;
    nav.on_heading(mag, mag.utime);
  }
  const double psi = nav.filter().x()(nav::kPsi);
  std::printf(
      "%zu GNSS headings; estimator heading %.2f deg, last GNSS %.2f deg; "
      "heading.other_ignored %lld\n",
      out.headings.size(), psi * 180 / M_PI, last.heading * 180 / M_PI,
      static_cast<long long>(nav.counter_value("heading.other_ignored")));
  EXPECT_NEAR(psi, last.heading, 2 * M_PI / 180);
  EXPECT_EQ(nav.counter_value("heading.other_ignored"),
            static_cast<std::int64_t>(out.headings.size()));
}

}  // namespace
}  // namespace tiller::sensors
