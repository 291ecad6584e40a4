// tiller-mavlink's transports (the thin glue around MavlinkNode): a UDP socket bound to
// ADDRESS:PORT that sends every frame to the configured peer and to each station heard in the
// last 10 s (at most 8), and a serial port (raw, 8N1, the configured baud) for a telemetry radio.
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

// Opens a serial port raw at `baud`; throws naming the device.
int open_serial(const std::string& device, int baud);

}  // namespace tiller::mavlink
