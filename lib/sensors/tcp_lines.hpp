// A TCP client that reads newline-terminated lines (the Water Linked DVL's JSON protocol, and any
// such sensor): connects to host:port (IPv4 numeric or a name), reads what has arrived within a
// poll's timeout and hands each complete line (without its "\n" or "\r\n") to a callback. A line
// longer than max_line is dropped whole and counted; a closed or failed connection is counted and
// retried no sooner than reconnect_s later, so the caller's loop keeps its rate with the device
// gone. The buffer is allocated once.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace tiller::sensors {

class TcpLineClient {
 public:
  TcpLineClient(std::string host, int port, std::size_t max_line = 8192, double reconnect_s = 1.0);
  ~TcpLineClient();
  TcpLineClient(const TcpLineClient&) = delete;
  TcpLineClient& operator=(const TcpLineClient&) = delete;

  // Connects if not connected (and the retry time has come), then waits up to timeout_ms for
  // data and delivers the complete lines. Returns the number of lines delivered.
  int poll(int timeout_ms, const std::function<void(std::string_view)>& on_line);

  bool connected() const { return fd_ >= 0; }
  std::int64_t connects() const { return connects_; }
  std::int64_t disconnects() const { return disconnects_; }
  std::int64_t overlong() const { return overlong_; }
  const std::string& last_error() const { return error_; }

 private:
  void close_socket(const std::string& why);
  bool try_connect();
  std::string host_;
  int port_;
  std::size_t max_line_;
  double reconnect_s_;
  int fd_ = -1;
  double next_try_ = 0;  // monotonic s
  std::vector<char> buf_;
  std::size_t used_ = 0;
  bool skipping_ = false;  // inside an over-long line: drop until its end
  std::int64_t connects_ = 0, disconnects_ = 0, overlong_ = 0;
  std::string error_;
};

}  // namespace tiller::sensors
