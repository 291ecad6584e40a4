#include "nmea_feed.hpp"

#include <GeographicLib/Geodesic.hpp>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "runtime/channels.hpp"
#include "runtime/live.hpp"
#include "sensors/gpsd_client.hpp"

extern char** environ;

namespace tiller::sensors::test {

namespace {
// Field `field` (0: "$GPxxx") of sentence `s`.
std::string field_of(const std::string& s, int field) {
  std::size_t a = 0;
  for (int i = 0; i < field; ++i) a = s.find(',', a) + 1;
  return s.substr(a, s.find_first_of(",*", a) - a);
}
// `s` with field `field` replaced by `value` (the checksum is not redone).
std::string with_field(const std::string& s, int field, const std::string& value) {
  std::size_t a = 0;
  for (int i = 0; i < field; ++i) a = s.find(',', a) + 1;
  return s.substr(0, a) + value + s.substr(s.find_first_of(",*", a));
}
// "$BODY*hh\r\n" again with the checksum of BODY.
std::string resum(const std::string& s) {
  const std::size_t star = s.find('*');
  const std::string body = s.substr(1, star - 1);
  char cs[8];
  std::snprintf(cs, sizeof cs, "*%02X\r\n", sim::nmea::checksum(body));
  return "$" + body + cs;
}
std::string one(std::size_t (*f)(const sim::nmea::Fix&, char*, std::size_t),
                const sim::nmea::Fix& fix) {
  char b[sim::nmea::kMaxEpochBytes];
  return std::string(b, f(fix, b, sizeof b));
}
}  // namespace

std::vector<Epoch> track(int n, double period_s) {
  std::vector<Epoch> out;
  const GeographicLib::Geodesic& g = GeographicLib::Geodesic::WGS84();
  for (int k = 0; k < n; ++k) {
    Epoch e;
    sim::nmea::Fix& f = e.fix;
    f.utc_us = kStartUtc + static_cast<TimeUs>(k * period_s * 1e6 + 0.5);
    f.valid = true;
    g.Direct(59.437, 10.6612, 0.0, 2.0 * k * period_s, f.latitude_deg, f.longitude_deg);
    f.altitude_msl_m = 12.3;
    f.geoid_separation_m = 39.8;
    f.satellites = 9;
    f.hdop = 0.9;
    f.vdop = 1.3;
    f.pdop = 1.6;
    f.speed_m_s = 2.0;
    f.course_rad = 0;
    f.std_north_m = 1.5;
    f.std_east_m = 1.2;
    f.std_up_m = 2.8;
    out.push_back(e);
  }
  return out;
}

std::string text(const std::vector<Epoch>& epochs) {
  using namespace sim::nmea;
  std::string all;
  for (const Epoch& e : epochs) {
    sim::nmea::Fix rmc_fix = e.fix;
    rmc_fix.utc_us += e.rmc_date_shift;
    std::string rmc_text = one(rmc, rmc_fix);
    if (e.rmc_date_shift != 0)  // the date (field 9) from the shifted time, the rest unshifted
      rmc_text = resum(with_field(one(rmc, e.fix), 9, field_of(rmc_text, 9)));
    struct Part {
      const char* type;
      std::string s;
    } parts[] = {{"GGA", one(gga, e.fix)},
                 {"GSA", one(gsa, e.fix)},
                 {"GSV", one(gsv, e.fix)},
                 {"GST", e.gst && e.fix.valid ? one(gst, e.fix) : ""},
                 {"RMC", rmc_text}};
    for (Part& p : parts) {
      if (p.s.empty()) continue;
      if (!e.latitude_text.empty() && e.fix.valid &&
          (p.s.compare(3, 3, "GGA") == 0 || p.s.compare(3, 3, "RMC") == 0))
        p.s = resum(with_field(p.s, p.s.compare(3, 3, "GGA") == 0 ? 2 : 3, e.latitude_text));
      for (const std::string& c : e.corrupt)
        if (c == p.type) p.s[p.s.find('*') + 1] ^= 0x01;  // one bit of the checksum off
      all += p.s;
    }
    if (!e.hdt.empty()) {
      const std::string body = "GPHDT," + e.hdt + ",T";
      char cs[8];
      std::snprintf(cs, sizeof cs, "*%02X\r\n", sim::nmea::checksum(body));
      all += "$" + body + cs;
    }
  }
  return all;
}

void Capture::publish(std::string_view ch, const std::uint8_t* d, int n) {
  if (ch == "TILLER_GNSS") {
    gnss_fix_t m;
    if (m.decode(d, 0, n) == n) fixes.push_back(m);
  } else if (ch == "TILLER_HEADING") {
    heading_t h;
    if (h.decode(d, 0, n) == n) headings.push_back(h);
  } else if (ch == "TILLER_HEARTBEAT_GNSS") {
    hb.decode(d, 0, n);
  }
}

std::vector<gnss_fix_t> Capture::with_fix() const {
  std::vector<gnss_fix_t> out;
  for (const auto& f : fixes)
    if (f.fix_type != gnss_fix_t::FIX_NONE && f.gnss_utime > 0) out.push_back(f);
  return out;
}

std::string play(const std::vector<Epoch>& epochs, const std::string& port, double cycle_s,
                 GnssNode& node, Capture& out) {
  char path[] = "/tmp/tiller_nmea_XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) return "mkstemp failed";
  close(fd);
  std::ofstream(path, std::ios::binary) << text(epochs);
  char cycle[32];
  std::snprintf(cycle, sizeof cycle, "%g", cycle_s);
  const char* argv[] = {"gpsfake", "-1", "-q", "-c", cycle, "-P", port.c_str(), path, nullptr};
  pid_t fake = -1;
  if (posix_spawnp(&fake, argv[0], nullptr, nullptr, const_cast<char**>(argv), environ) != 0)
    return "cannot start gpsfake";
  GnssParams p = node.params();
  p.port = port;
  node.attach(&out);
  std::string why = "not tried";
  {
    LiveExecutor ex(channels::kDefaultLcmUrl);
    GpsdClient client(p, node, ex);
    for (int i = 0; i < 200 && !why.empty(); ++i) {
      why = client.connect(wall_time_us());
      if (!why.empty()) usleep(50'000);
    }
    // gpsfake starts the log when a client connects: the log's length in sentences times
    // cycle_s, and 1.5 s for gpsd to find the device and report.
    std::size_t lines = 0;
    for (const char c : text(epochs)) lines += c == '\n';
    const TimeUs end = wall_time_us() + from_seconds(static_cast<double>(lines) * cycle_s + 1.5);
    TimeUs next_tick = 0;
    while (why.empty() && wall_time_us() < end) {
      client.pump(wall_time_us());
      const TimeUs now = wall_time_us();
      if (now >= next_tick) {
        node.tick(now);
        next_tick = now + 100'000;
      }
      usleep(5'000);
    }
  }  // the client disconnects: gpsfake -1 ends once its log is done and no client is left
  bool done = false;
  for (int i = 0; i < 100 && !done; ++i) {
    done = waitpid(fake, nullptr, WNOHANG) == fake;
    if (!done) usleep(20'000);
    if (i == 5) kill(fake, SIGTERM);
  }
  if (!done) {
    kill(fake, SIGKILL);
    waitpid(fake, nullptr, 0);
  }
  node.tick(wall_time_us() + kUsPerSecond);  // whatever an epoch still holds
  std::remove(path);
  return why;
}

}  // namespace tiller::sensors::test
