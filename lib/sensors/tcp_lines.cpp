#include "sensors/tcp_lines.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

namespace tiller::sensors {

namespace {
double monotonic_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

TcpLineClient::TcpLineClient(std::string host, int port, std::size_t max_line, double reconnect_s,
                             double connect_timeout_s)
    : host_(std::move(host)),
      port_(port),
      max_line_(max_line),
      reconnect_s_(reconnect_s),
      connect_timeout_s_(connect_timeout_s),
      buf_(max_line + 1) {}

TcpLineClient::~TcpLineClient() {
  if (fd_ >= 0) ::close(fd_);
}

std::string TcpLineClient::where() const {
  return host_ + ":" + std::to_string(port_);
}

void TcpLineClient::close_socket(const std::string& why, double now_s) {
  if (fd_ >= 0) {
    ::close(fd_);
    if (state_ == State::kUp) ++disconnects_;
  }
  fd_ = -1;
  state_ = State::kDown;
  used_ = 0;
  skipping_ = false;
  error_ = why;
  next_try_ = now_s + reconnect_s_;
}

bool TcpLineClient::start_connect(double now_s) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const std::string port = std::to_string(port_);
  if (const int rc = ::getaddrinfo(host_.c_str(), port.c_str(), &hints, &res); rc != 0) {
    close_socket(host_ + ": " + ::gai_strerror(rc), now_s);
    return false;
  }
  fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd_ < 0) {
    ::freeaddrinfo(res);
    close_socket(std::string("socket: ") + std::strerror(errno), now_s);
    return false;
  }
  const int rc = ::connect(fd_, res->ai_addr, res->ai_addrlen);
  const int err = errno;
  ::freeaddrinfo(res);
  state_ = State::kConnecting;
  connect_started_ = now_s;
  if (rc != 0 && err != EINPROGRESS) {
    close_socket(where() + ": " + std::strerror(err), now_s);
    return false;
  }
  if (rc == 0) return finish_connect(now_s);
  return true;
}

bool TcpLineClient::finish_connect(double now_s) {
  pollfd p{fd_, POLLOUT, 0};
  if (::poll(&p, 1, 0) <= 0) return false;  // still under way
  int err = 0;
  socklen_t len = sizeof err;
  if (::getsockopt(fd_, SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
  if (err != 0) {
    close_socket(where() + ": " + std::strerror(err), now_s);
    return false;
  }
  state_ = State::kUp;
  ++connects_;
  error_.clear();
  return true;
}

TcpLineClient::State TcpLineClient::service(double now_s) {
  if (state_ == State::kDown && now_s >= next_try_) start_connect(now_s);
  if (state_ == State::kConnecting && !finish_connect(now_s) && state_ == State::kConnecting &&
      now_s - connect_started_ >= connect_timeout_s_) {
    char b[64];
    std::snprintf(b, sizeof b, ": no answer within %.1f s (connect timed out)", connect_timeout_s_);
    close_socket(where() + b, now_s);
  }
  return state_;
}

int TcpLineClient::poll(int timeout_ms, const std::function<void(std::string_view)>& on_line) {
  double now = monotonic_s();
  if (state_ == State::kDown) service(now);
  if (state_ == State::kConnecting) {
    pollfd p{fd_, POLLOUT, 0};
    ::poll(&p, 1, timeout_ms);
    service(monotonic_s());
    if (state_ != State::kUp) {
      if (state_ == State::kDown && timeout_ms > 0) ::poll(nullptr, 0, timeout_ms);
      return 0;  // keep the caller's rate
    }
  } else if (state_ == State::kDown) {
    if (timeout_ms > 0) ::poll(nullptr, 0, timeout_ms);  // keep the caller's rate
    return 0;
  }
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) <= 0) return 0;
  now = monotonic_s();
  return read_available(now, on_line);
}

int TcpLineClient::read_available(double now_s,
                                  const std::function<void(std::string_view)>& on_line) {
  if (state_ == State::kConnecting) finish_connect(now_s);
  if (state_ != State::kUp) return 0;
  int lines = 0;
  for (;;) {
    const ssize_t n = ::recv(fd_, buf_.data() + used_, buf_.size() - used_, 0);
    if (n == 0) {
      close_socket("closed by the device", now_s);
      return lines;
    }
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) return lines;
      if (errno == EINTR) continue;
      close_socket(std::string("recv: ") + std::strerror(errno), now_s);
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
