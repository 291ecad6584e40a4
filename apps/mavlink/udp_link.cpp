// tiller-mavlink's UDP and serial transports (udp_link.hpp).
#include "udp_link.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

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
  // A radio has no modem lines and (SiK's default) no RTS/CTS: a port left with hardware flow
  // control stalls every write, one without CLOCAL hangs up on a carrier it never sees.
  t.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | CSTOPB | HUPCL);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  t.c_cc[VMIN] = 1;  // with O_NONBLOCK: EAGAIN when empty, so a read of 0 means a hang-up
  t.c_cc[VTIME] = 0;
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
  ::tcflush(fd, TCIOFLUSH);
  return fd;
}

SerialLink::SerialLink(std::string device, int baud)
    : device_(std::move(device)), baud_(baud), fd_(open_serial(device_, baud)) {
  queue_.reserve(kQueueBytes);
}

SerialLink::~SerialLink() {
  if (fd_ >= 0) ::close(fd_);
}

void SerialLink::lose(const char* what, int err) {
  std::fprintf(stderr, "tiller-mavlink: serial %s: %s %s; closed, reopening it every second\n",
               device_.c_str(), what, err ? std::strerror(err) : "end of file (hung up)");
  ::close(fd_);
  fd_ = -1;
  queue_.clear();  // the rest of a frame is worthless to a new radio
  reopen_failed_ = false;
}

long SerialLink::receive(std::uint8_t* buf, std::size_t size) {
  if (fd_ < 0) return -1;
  const long n = ::read(fd_, buf, size);
  if (n > 0) return n;
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return 0;
  lose("read:", n < 0 ? errno : 0);
  return -1;
}

void SerialLink::flush() {
  if (fd_ < 0 || queue_.empty()) return;
  const long w = ::write(fd_, queue_.data(), queue_.size());
  if (w < 0) {
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) lose("write:", errno);
    return;
  }
  queue_.erase(queue_.begin(), queue_.begin() + w);
}

void SerialLink::send(const std::uint8_t* data, std::size_t n) {
  if (fd_ < 0) return;
  flush();
  if (fd_ < 0) return;
  if (!queue_.empty()) {  // the port is behind: after what is queued, or not at all
    if (queue_.size() + n > kQueueBytes) {
      ++dropped_;
      return;
    }
    queue_.insert(queue_.end(), data, data + n);
    return;
  }
  long w = ::write(fd_, data, n);
  if (w < 0) {
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      lose("write:", errno);
      return;
    }
    w = 0;
  }
  if (static_cast<std::size_t>(w) < n) {
    if (n - static_cast<std::size_t>(w) > kQueueBytes) {  // cannot happen: frames are < 300 bytes
      ++dropped_;
      return;
    }
    queue_.insert(queue_.end(), data + w, data + n);
  }
}

bool SerialLink::reopen() {
  if (fd_ >= 0) return true;
  try {
    fd_ = open_serial(device_, baud_);
  } catch (const std::exception& e) {
    if (!reopen_failed_) std::fprintf(stderr, "tiller-mavlink: %s; still trying\n", e.what());
    reopen_failed_ = true;
    return false;
  }
  std::fprintf(stderr, "tiller-mavlink: serial %s: open again at %d baud\n", device_.c_str(),
               baud_);
  return true;
}

}  // namespace tiller::mavlink
