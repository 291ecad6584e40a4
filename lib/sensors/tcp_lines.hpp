// A TCP client that reads newline-terminated lines (the Water Linked DVL's JSON protocol, and any
// such sensor): connects to host:port (IPv4 numeric or a name), reads what has arrived and hands
// each complete line (without its "\n" or "\r\n") to a callback. A line longer than max_line is
// dropped whole and counted; a closed or failed connection is counted and retried no sooner than
// reconnect_s later, so the caller's loop keeps its rate with the device gone. The buffer is
// allocated once.
//
// Two ways to use it:
//   * blocking with a timeout: poll(timeout_ms, on_line) connects when due, waits up to
//     timeout_ms for data and delivers the lines (a loop of its own; dvl_a50_test);
//   * inside an event loop (the live executor, sensors/dvl_link.hpp): service(now_s) starts a
//     connection when one is due, without blocking (a non-blocking connect, given up after
//     connect_timeout_s), and finishes one that completed; fd() is the socket to watch for
//     readability (-1 while down); read_available(now_s, on_line) reads what is there without
//     waiting. `now_s` is the caller's clock in seconds (any clock, the same one every call);
//     poll() uses CLOCK_MONOTONIC.
// The name is resolved with getaddrinfo, which may block on a DNS lookup: give a numeric address
// (the DVL's 192.168.194.95) in a live loop.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace tiller::sensors {

class TcpLineClient {
 public:
  enum class State { kDown, kConnecting, kUp };

  TcpLineClient(std::string host, int port, std::size_t max_line = 8192, double reconnect_s = 1.0,
                double connect_timeout_s = 3.0);
  ~TcpLineClient();
  TcpLineClient(const TcpLineClient&) = delete;
  TcpLineClient& operator=(const TcpLineClient&) = delete;

  // Connects if not connected (and the retry time has come), then waits up to timeout_ms for
  // data and delivers the complete lines. Returns the number of lines delivered.
  int poll(int timeout_ms, const std::function<void(std::string_view)>& on_line);

  // ---- event-loop API (see above)
  // Down and due: starts a connection. Connecting: finishes it if it completed, gives it up
  // after connect_timeout_s. Returns the state afterwards.
  State service(double now_s);
  // Reads what has arrived, without waiting, and delivers the complete lines (finishing a
  // connection that completed first). A closed or failed connection is closed here (the
  // state goes kDown, fd() -1). Returns the number of lines delivered.
  int read_available(double now_s, const std::function<void(std::string_view)>& on_line);
  // The socket while connecting or connected, else -1.
  int fd() const { return fd_; }
  State state() const { return state_; }

  bool connected() const { return state_ == State::kUp; }
  const std::string& host() const { return host_; }
  int port() const { return port_; }
  std::int64_t connects() const { return connects_; }
  std::int64_t disconnects() const { return disconnects_; }
  std::int64_t overlong() const { return overlong_; }
  // Why the last connection failed or ended ("" while connected or before the first try).
  const std::string& last_error() const { return error_; }

 private:
  void close_socket(const std::string& why, double now_s);
  bool start_connect(double now_s);
  bool finish_connect(double now_s);  // true: connected
  std::string where() const;
  std::string host_;
  int port_;
  std::size_t max_line_;
  double reconnect_s_, connect_timeout_s_;
  int fd_ = -1;
  State state_ = State::kDown;
  double next_try_ = -1e300;  // caller's clock, s
  double connect_started_ = 0;
  std::vector<char> buf_;
  std::size_t used_ = 0;
  bool skipping_ = false;  // inside an over-long line: drop until its end
  std::int64_t connects_ = 0, disconnects_ = 0, overlong_ = 0;
  std::string error_;
};

}  // namespace tiller::sensors
