// NMEA 0183 sentences of one GNSS epoch, as a receiver sends them to gpsd: GGA (fix, position,
// altitude), GSA (fix mode, satellites used, DOPs), GSV (satellites in view: gpsd's SKY report,
// where tiller-gnss reads the count), GST (the receiver's 1-sigma position errors) and RMC
// (status, speed and course over ground, date). Written into a caller's buffer with
// snprintf (no heap), each "$<talker><type>,...*hh\r\n" where hh is the XOR of every byte between
// '$' and '*' in two upper-case hex digits (NMEA 0183 v4.11, section 5.3; the field layouts as
// gpsd documents them: https://gpsd.gitlab.io/gpsd/NMEA.html). Latitude ddmm.mmmmmmm and
// longitude dddmm.mmmmmmm (1e-7 minute = 0.2 mm), time hhmmss.ss UTC, speed in knots (1852 m /
// 3600 s), course in degrees true [0, 360). No fix: GGA quality 0 and RMC status V with empty
// position fields, GSA mode 1, no GST.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/time.hpp"

namespace tiller::sim::nmea {

// XOR of the bytes of `body` (the text between '$' and '*').
std::uint8_t checksum(std::string_view body);

struct Fix {
  TimeUs utc_us = 0;  // us since 1970-01-01 UTC, >= 0
  bool valid = false;
  double latitude_deg = 0, longitude_deg = 0;  // WGS84
  double altitude_msl_m = 0;                   // above the geoid
  double geoid_separation_m = 0;               // ellipsoid - geoid
  int satellites = 0;                          // used, 0..12 are listed in GSA
  double hdop = 0, vdop = 0, pdop = 0;
  double speed_m_s = 0, course_rad = 0;  // over ground, course clockwise from true north
  double std_north_m = 0, std_east_m = 0, std_up_m = 0;  // 1-sigma (GST)
};

// One sentence each; returns its length, 0 when `cap` is too small (nothing usable written).
std::size_t gga(const Fix& f, char* buf, std::size_t cap);
std::size_t gsa(const Fix& f, char* buf, std::size_t cap);
std::size_t gsv(const Fix& f, char* buf, std::size_t cap);  // every GSV sentence of the epoch
std::size_t gst(const Fix& f, char* buf, std::size_t cap);
std::size_t rmc(const Fix& f, char* buf, std::size_t cap);
// The epoch in the order GGA, GSA, GSV, GST (with a fix), RMC; 0 when `cap` is too small.
std::size_t epoch(const Fix& f, char* buf, std::size_t cap);

inline constexpr std::size_t kMaxEpochBytes = 1024;

}  // namespace tiller::sim::nmea
