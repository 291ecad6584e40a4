// tiller-sim's NMEA output (I/O glue, used by apps/sim): a pseudo-terminal that gpsd reads as
// it would a receiver on a serial port. posix_openpt(O_RDWR | O_NOCTTY), grantpt, unlockpt,
// ptsname_r give the slave's path (/dev/pts/N); the simulator keeps the slave open itself, in
// raw mode (cfmakeraw: no echo, no line editing), so the terminal stays up while gpsd opens and
// closes it and text written before gpsd is there is not echoed back. Writes to the master are
// non-blocking: when nobody reads and the buffer is full, the epoch is dropped and counted, and
// the simulator never waits. An optional symlink (tiller-sim --nmea-link PATH) gives launch
// files a fixed name for gpsd; it is replaced if it is a symlink, refused if it is anything else,
// and removed at exit.
#pragma once

#include <cstdint>
#include <string>

#include "sim/sensor_suite.hpp"

namespace tiller::sim {

class NmeaPty : public NmeaSink {
 public:
  // Throws std::runtime_error naming the call that failed (and the link path).
  explicit NmeaPty(const std::string& link_path = "");
  ~NmeaPty() override;
  NmeaPty(const NmeaPty&) = delete;
  NmeaPty& operator=(const NmeaPty&) = delete;

  void write(const char* data, std::size_t n) override;
  const std::string& slave_path() const { return slave_path_; }
  const std::string& link_path() const { return link_path_; }
  std::int64_t dropped() const { return dropped_; }  // epochs not written (buffer full)
  std::int64_t written() const { return written_; }

 private:
  int master_ = -1, slave_ = -1;
  std::string slave_path_, link_path_;
  std::int64_t dropped_ = 0, written_ = 0;
};

}  // namespace tiller::sim
