// tiller-mavlink's UDP and serial transports (udp_link.hpp).
#include "udp_link.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tiller::mavlink {

namespace {
constexpr TimeUs kPeerTimeout = 10 * kUsPerSecond;
constexpr std::size_t kMaxPeers = 8;
bool same(const sockaddr_in& a, const sockaddr_in& b) {
  return a.sin_addr.s_addr == b.sin_addr.s_addr && a.sin_port == b.sin_port;
}
}  // namespace

sockaddr_in parse_address(const std::string& s) {
  const auto colon = s.rfind(':');
  sockaddr_in a{};
  a.sin_family = AF_INET;
  if (colon == std::string::npos ||
      inet_pton(AF_INET, s.substr(0, colon).c_str(), &a.sin_addr) != 1)
    throw std::runtime_error("'" + s + "': expected IPV4ADDRESS:PORT, e.g. 127.0.0.1:14550");
  const int port = std::atoi(s.c_str() + colon + 1);
  if (port <= 0 || port > 65535) throw std::runtime_error("'" + s + "': the port must be 1..65535");
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  return a;
}

UdpLink::UdpLink(const std::string& bind_to, const std::string& peer) {
  const sockaddr_in b = parse_address(bind_to);
  peer_ = parse_address(peer);
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("UDP socket: ") + std::strerror(errno));
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&b), sizeof b) != 0) {
    const int e = errno;
    ::close(fd_);
    throw std::runtime_error("cannot listen on UDP " + bind_to + ": " + std::strerror(e));
  }
  heard_.reserve(kMaxPeers);
}

UdpLink::~UdpLink() {
  if (fd_ >= 0) ::close(fd_);
}

long UdpLink::receive(std::uint8_t* buf, std::size_t size, TimeUs now) {
  sockaddr_in from{};
  socklen_t len = sizeof from;
  const long n = ::recvfrom(fd_, buf, size, 0, reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) return -1;
  for (Peer& p : heard_) {
    if (same(p.addr, from)) {
      p.heard = now;
      return n;
    }
  }
  for (Peer& p : heard_) {
    if (now - p.heard > kPeerTimeout) {
      p = {from, now};
      return n;
    }
  }
  if (heard_.size() < kMaxPeers) heard_.push_back({from, now});
  return n;
}

void UdpLink::send(const std::uint8_t* data, std::size_t n, TimeUs now) {
  bool peer_heard = false;
  for (const Peer& p : heard_) {
    if (now - p.heard > kPeerTimeout) continue;
    if (same(p.addr, peer_)) peer_heard = true;
    ::sendto(fd_, data, n, 0, reinterpret_cast<const sockaddr*>(&p.addr), sizeof p.addr);
  }
  if (!peer_heard)
    ::sendto(fd_, data, n, 0, reinterpret_cast<const sockaddr*>(&peer_), sizeof peer_);
}

int open_serial(const std::string& device, int baud) {
  const int fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("serial " + device + ": " + std::strerror(errno));
  termios t{};
  if (::tcgetattr(fd, &t) != 0) {
    ::close(fd);
    throw std::runtime_error("serial " + device + ": not a terminal device");
  }
  ::cfmakeraw(&t);
  speed_t s = B57600;
  switch (baud) {
    case 9600:
      s = B9600;
      break;
    case 19200:
      s = B19200;
      break;
    case 38400:
      s = B38400;
      break;
    case 57600:
      s = B57600;
      break;
    case 115200:
      s = B115200;
      break;
    case 230400:
      s = B230400;
      break;
    case 460800:
      s = B460800;
      break;
    case 921600:
      s = B921600;
      break;
    default:
      ::close(fd);
      throw std::runtime_error("serial " + device + ": baud " + std::to_string(baud) +
                               " is not one of 9600, 19200, 38400, 57600, 115200, 230400, "
                               "460800, 921600");
  }
  ::cfsetispeed(&t, s);
  ::cfsetospeed(&t, s);
  if (::tcsetattr(fd, TCSANOW, &t) != 0) {
    ::close(fd);
    throw std::runtime_error("serial " + device + ": cannot set it raw");
  }
  return fd;
}

}  // namespace tiller::mavlink
