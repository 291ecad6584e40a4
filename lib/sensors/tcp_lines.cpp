#include "sensors/tcp_lines.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

namespace tiller::sensors {

namespace {
double monotonic_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

TcpLineClient::TcpLineClient(std::string host, int port, std::size_t max_line, double reconnect_s)
    : host_(std::move(host)),
      port_(port),
      max_line_(max_line),
      reconnect_s_(reconnect_s),
      buf_(max_line + 1) {}

TcpLineClient::~TcpLineClient() {
  if (fd_ >= 0) ::close(fd_);
}

void TcpLineClient::close_socket(const std::string& why) {
  if (fd_ >= 0) {
    ::close(fd_);
    ++disconnects_;
  }
  fd_ = -1;
  used_ = 0;
  skipping_ = false;
  error_ = why;
  next_try_ = monotonic_s() + reconnect_s_;
}

bool TcpLineClient::try_connect() {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const std::string port = std::to_string(port_);
  if (const int rc = ::getaddrinfo(host_.c_str(), port.c_str(), &hints, &res); rc != 0) {
    close_socket(host_ + ": " + ::gai_strerror(rc));
    return false;
  }
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    ::freeaddrinfo(res);
    close_socket(std::string("socket: ") + std::strerror(errno));
    return false;
  }
  const int rc = ::connect(fd_, res->ai_addr, res->ai_addrlen);
  ::freeaddrinfo(res);
  if (rc != 0) {
    const std::string why = host_ + ":" + port + ": " + std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    close_socket(why);
    return false;
  }
  ::fcntl(fd_, F_SETFL, ::fcntl(fd_, F_GETFL) | O_NONBLOCK);
  ++connects_;
  error_.clear();
  return true;
}

int TcpLineClient::poll(int timeout_ms, const std::function<void(std::string_view)>& on_line) {
  if (fd_ < 0) {
    if (monotonic_s() < next_try_ || !try_connect()) {
      if (timeout_ms > 0) ::poll(nullptr, 0, timeout_ms);  // keep the caller's rate
      return 0;
    }
  }
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) <= 0) return 0;
  int lines = 0;
  for (;;) {
    const ssize_t n = ::recv(fd_, buf_.data() + used_, buf_.size() - used_, 0);
    if (n == 0) {
      close_socket("closed by the device");
      return lines;
    }
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return lines;
      if (errno == EINTR) continue;
      close_socket(std::string("recv: ") + std::strerror(errno));
      return lines;
    }
    used_ += static_cast<std::size_t>(n);
    std::size_t start = 0;
    for (std::size_t i = 0; i < used_; ++i) {
      if (buf_[i] != '\n') continue;
      std::size_t end = i;
      if (end > start && buf_[end - 1] == '\r') --end;
      if (!skipping_) {
        on_line(std::string_view(buf_.data() + start, end - start));
        ++lines;
      }
      skipping_ = false;
      start = i + 1;
    }
    std::memmove(buf_.data(), buf_.data() + start, used_ - start);
    used_ -= start;
    if (used_ > max_line_) {  // no end in sight: drop this line
      if (!skipping_) ++overlong_;
      skipping_ = true;
      used_ = 0;
    }
  }
}

}  // namespace tiller::sensors
