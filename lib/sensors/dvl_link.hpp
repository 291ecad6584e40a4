// The live glue between the DVL's TCP connection and a DvlNode (tiller-dvl's I/O): a
// TcpLineClient (sensors/tcp_lines.hpp) to the DVL's host:port, its socket watched by the live
// executor and read without blocking, every complete line handed to the node with its receive
// time. The connection is made without blocking the loop (a non-blocking connect, given up after
// connect_timeout_s) and tried again every reconnect_s (a timerfd) while it is down; a lost or
// refused connection is said once on stderr and in the node's heartbeat (FAULT, set_link()).
#pragma once

#include <string>

#include "runtime/live.hpp"
#include "sensors/dvl_node.hpp"
#include "sensors/tcp_lines.hpp"

namespace tiller::sensors {

class DvlLink {
 public:
  DvlLink(const DvlParams& p, DvlNode& node, LiveExecutor& ex);
  ~DvlLink();
  DvlLink(const DvlLink&) = delete;
  DvlLink& operator=(const DvlLink&) = delete;
  // Starts a connection attempt now (if down), as the timer does every reconnect_s.
  void service(TimeUs now);
  const TcpLineClient& client() const { return client_; }

 private:
  void on_readable(TimeUs now);
  void on_timer(TimeUs now);
  void after(TimeUs now);  // follows the client's socket and state into the executor and node
  DvlNode& node_;
  LiveExecutor* ex_;
  double reconnect_s_;
  TcpLineClient client_;
  int timer_fd_ = -1;
  int watched_ = -1;  // the socket the executor watches
  bool up_ = false;
  std::string said_;
};

}  // namespace tiller::sensors
