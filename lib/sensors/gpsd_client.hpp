// The live glue between gpsd and a GnssNode (tiller-gnss's I/O): a libgps connection
// (gps_open, gps_stream WATCH_ENABLE | WATCH_JSON), its socket watched by the live executor,
// every report read with gps_read while gps_waiting and handed to the node with the receive
// time. A lost or refused connection is said once on stderr and in the node's heartbeat
// (FAULT) and tried again every reconnect period (a timerfd).
#pragma once

#include <memory>
#include <string>

#include "runtime/live.hpp"
#include "sensors/gnss_node.hpp"

namespace tiller::sensors {

class GpsdClient {
 public:
  GpsdClient(const GnssParams& p, GnssNode& node, LiveExecutor& ex);
  ~GpsdClient();
  GpsdClient(const GpsdClient&) = delete;
  GpsdClient& operator=(const GpsdClient&) = delete;
  // Tries to connect now; "" on success, else why not.
  std::string connect(TimeUs now);
  // Reads every waiting report into the node (what the executor calls when the socket is
  // readable; tests call it directly). False when the connection dropped.
  bool pump(TimeUs now);

 private:
  void drop(const std::string& why, TimeUs now);
  static void att_workaround(struct gps_data_t& d, const char* raw);
  char raw_[4096] = {};  // the last report's JSON text
  void on_timer(TimeUs now);
  GnssParams p_;
  GnssNode& node_;
  LiveExecutor* ex_;
  std::unique_ptr<struct gps_data_t> data_;
  bool open_ = false;
  int timer_fd_ = -1;
  std::string said_;
};

}  // namespace tiller::sensors
