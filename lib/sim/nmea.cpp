#include "sim/nmea.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>

namespace tiller::sim::nmea {

namespace {

constexpr double kKnotPerMS = 3600.0 / 1852.0;

struct Utc {
  char hms[48];   // hhmmss.ss (sized for any int, as -Wformat-truncation asks)
  char date[40];  // ddmmyy
};

Utc utc_of(TimeUs us) {
  if (us < 0) us = 0;
  const std::time_t s = static_cast<std::time_t>(us / kUsPerSecond);
  const int cs = static_cast<int>((us % kUsPerSecond) / 10'000);
  std::tm tm{};
  gmtime_r(&s, &tm);
  Utc u{};
  std::snprintf(u.hms, sizeof u.hms, "%02d%02d%02d.%02d", tm.tm_hour, tm.tm_min, tm.tm_sec, cs);
  std::snprintf(u.date, sizeof u.date, "%02d%02d%02d", tm.tm_mday, tm.tm_mon + 1, tm.tm_year % 100);
  return u;
}

// "ddmm.mmmmmmm,N" (deg_digits 2) or "dddmm.mmmmmmm,E" (3), rounded to 1e-7 minute.
void angle(char* out, std::size_t cap, double deg, int deg_digits, char pos, char neg) {
  const long long v = std::llround(std::fabs(deg) * 60.0 * 1e7);  // 1e-7 minutes
  const long long per_deg = 60LL * 10'000'000;
  const long long d = v / per_deg, rem = v % per_deg;
  std::snprintf(out, cap, "%0*lld%02lld.%07lld,%c", deg_digits, d, rem / 10'000'000,
                rem % 10'000'000, deg < 0 ? neg : pos);
}

// buf holds "$BODY" of n bytes: appends "*HH\r\n". Returns the total length, 0 if it does not fit.
std::size_t finish(char* buf, std::size_t cap, int n) {
  if (n <= 0 || static_cast<std::size_t>(n) + 6 > cap) return 0;
  const std::uint8_t c = checksum(std::string_view(buf + 1, static_cast<std::size_t>(n - 1)));
  const int m = std::snprintf(buf + n, cap - static_cast<std::size_t>(n), "*%02X\r\n", c);
  return static_cast<std::size_t>(n + m);
}

int clamp_n(int n, std::size_t cap) {
  return n < 0 || static_cast<std::size_t>(n) >= cap ? -1 : n;
}

}  // namespace

std::uint8_t checksum(std::string_view body) {
  std::uint8_t c = 0;
  for (const char ch : body) c ^= static_cast<std::uint8_t>(ch);
  return c;
}

std::size_t gga(const Fix& f, char* buf, std::size_t cap) {
  const Utc u = utc_of(f.utc_us);
  int n;
  if (f.valid) {
    char lat[64], lon[64];
    angle(lat, sizeof lat, f.latitude_deg, 2, 'N', 'S');
    angle(lon, sizeof lon, f.longitude_deg, 3, 'E', 'W');
    n = std::snprintf(buf, cap, "$GPGGA,%s,%s,%s,1,%02d,%.1f,%.3f,M,%.3f,M,,", u.hms, lat, lon,
                      f.satellites, f.hdop, f.altitude_msl_m, f.geoid_separation_m);
  } else {
    n = std::snprintf(buf, cap, "$GPGGA,%s,,,,,0,00,,,M,,M,,", u.hms);
  }
  return finish(buf, cap, clamp_n(n, cap));
}

std::size_t gsa(const Fix& f, char* buf, std::size_t cap) {
  char prns[64] = "";
  std::size_t k = 0;
  for (int i = 0; i < 12; ++i) {
    const int w = i < f.satellites && f.valid
                      ? std::snprintf(prns + k, sizeof prns - k, "%02d,", 2 * i + 1)
                      : std::snprintf(prns + k, sizeof prns - k, ",");
    k += static_cast<std::size_t>(w);
  }
  int n;
  if (f.valid) {
    n = std::snprintf(buf, cap, "$GPGSA,A,3,%s%.1f,%.1f,%.1f", prns, f.pdop, f.hdop, f.vdop);
  } else {
    n = std::snprintf(buf, cap, "$GPGSA,A,1,%s,,", prns);
  }
  return finish(buf, cap, clamp_n(n, cap));
}

std::size_t gsv(const Fix& f, char* buf, std::size_t cap) {
  // The satellites GSA lists (PRN 2i + 1), spread over the sky, 4 to a sentence.
  const int n = f.valid ? std::clamp(f.satellites, 0, 12) : 0;
  const int sentences = std::max(1, (n + 3) / 4);
  std::size_t used = 0;
  for (int k = 0; k < sentences; ++k) {
    int w = std::snprintf(buf + used, cap - used, "$GPGSV,%d,%d,%02d", sentences, k + 1, n);
    if (w < 0 || used + static_cast<std::size_t>(w) >= cap) return 0;
    std::size_t len = static_cast<std::size_t>(w);
    for (int i = 4 * k; i < std::min(n, 4 * k + 4); ++i) {
      w = std::snprintf(buf + used + len, cap - used - len, ",%02d,%02d,%03d,%02d", 2 * i + 1,
                        15 + (37 * i) % 70, (97 * i) % 360, 38 + i % 7);
      if (w < 0 || used + len + static_cast<std::size_t>(w) >= cap) return 0;
      len += static_cast<std::size_t>(w);
    }
    const std::size_t m = finish(buf + used, cap - used, static_cast<int>(len));
    if (m == 0) return 0;
    used += m;
  }
  return used;
}

std::size_t gst(const Fix& f, char* buf, std::size_t cap) {
  const Utc u = utc_of(f.utc_us);
  const double rms = std::sqrt(f.std_north_m * f.std_north_m + f.std_east_m * f.std_east_m);
  const double major = std::fmax(f.std_north_m, f.std_east_m);
  const double minor = std::fmin(f.std_north_m, f.std_east_m);
  const double orient = f.std_north_m >= f.std_east_m ? 0.0 : 90.0;
  const int n = std::snprintf(buf, cap, "$GPGST,%s,%.3f,%.3f,%.3f,%.1f,%.3f,%.3f,%.3f", u.hms, rms,
                              major, minor, orient, f.std_north_m, f.std_east_m, f.std_up_m);
  return finish(buf, cap, clamp_n(n, cap));
}

std::size_t rmc(const Fix& f, char* buf, std::size_t cap) {
  const Utc u = utc_of(f.utc_us);
  int n;
  if (f.valid) {
    char lat[64], lon[64];
    angle(lat, sizeof lat, f.latitude_deg, 2, 'N', 'S');
    angle(lon, sizeof lon, f.longitude_deg, 3, 'E', 'W');
    double course = f.course_rad * 180.0 / M_PI;
    if (course < 0) course += 360.0;
    if (course >= 359.995) course = 0.0;  // would print as 360.00
    n = std::snprintf(buf, cap, "$GPRMC,%s,A,%s,%s,%.3f,%.2f,%s,,,A", u.hms, lat, lon,
                      f.speed_m_s * kKnotPerMS, course, u.date);
  } else {
    n = std::snprintf(buf, cap, "$GPRMC,%s,V,,,,,,,%s,,,N", u.hms, u.date);
  }
  return finish(buf, cap, clamp_n(n, cap));
}

std::size_t epoch(const Fix& f, char* buf, std::size_t cap) {
  std::size_t n = 0;
  for (auto* s : {&gga, &gsa, &gsv, &gst, &rmc}) {
    if (s == &gst && !f.valid) continue;
    const std::size_t k = s(f, buf + n, cap - n);
    if (k == 0) return 0;
    n += k;
  }
  return n;
}

}  // namespace tiller::sim::nmea
