// tiller-mavlink's transports (the thin glue around MavlinkNode): a UDP socket bound to
// ADDRESS:PORT that sends every frame to the configured peer and to each station heard in the
// last 10 s (at most 8), and a serial port (raw, 8N1, the configured baud, no flow control, modem
// lines ignored) for a telemetry radio, reopened when it goes away.
#pragma once

#include <netinet/in.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace tiller::mavlink {

sockaddr_in parse_address(const std::string& address_port);  // throws naming it

class UdpLink {
 public:
  UdpLink(const std::string& bind, const std::string& peer);
  ~UdpLink();
  int fd() const { return fd_; }
  // Reads one datagram (non-blocking); returns its size, or -1 when there is none. The sender
  // becomes a peer.
  long receive(std::uint8_t* buf, std::size_t size, TimeUs now);
  void send(const std::uint8_t* data, std::size_t n, TimeUs now);

 private:
  struct Peer {
    sockaddr_in addr;
    TimeUs heard;
  };
  int fd_ = -1;
  sockaddr_in peer_{};
  std::vector<Peer> heard_;
};

// Opens a serial port raw at `baud` (8N1, CLOCAL, no RTS/CTS, no XON/XOFF, non-blocking);
// throws naming the device.
int open_serial(const std::string& device, int baud);

// A telemetry radio's serial port. Frames go out whole: when the port takes only part of a frame
// (its buffer full: a radio slower than the telemetry, a station not reading) the rest is queued
// and written before anything else, and a frame that does not fit the queue (kQueueBytes) is
// dropped whole, so a slow link loses frames, never the framing. A port that hangs up or fails
// (a USB radio unplugged, a pty's other end closed) is closed, not spun on; reopen() opens the
// same path again (a radio plugged back in, its /dev/serial/by-id name back).
class SerialLink {
 public:
  static constexpr std::size_t kQueueBytes = 4096;
  SerialLink(std::string device, int baud);  // opens it; throws naming the device
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;
  int fd() const { return fd_; }  // -1 while the port is lost
  const std::string& device() const { return device_; }
  // Reads what there is (non-blocking): its size, 0 when nothing is waiting, -1 when the port
  // was lost with it (then closed: fd() was the old descriptor, now -1).
  long receive(std::uint8_t* buf, std::size_t size);
  void send(const std::uint8_t* data, std::size_t n);
  void flush();   // writes what is queued, as much as the port takes
  bool reopen();  // while lost: tries the path again; true when the port is open
  std::int64_t frames_dropped() const { return dropped_; }

 private:
  void lose(const char* what, int err);
  std::string device_;
  int baud_;
  int fd_ = -1;
  std::vector<std::uint8_t> queue_;
  std::int64_t dropped_ = 0;
  bool reopen_failed_ = false;  // said once per loss
};

}  // namespace tiller::mavlink
