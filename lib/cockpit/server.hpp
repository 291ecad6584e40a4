// The cockpit's HTTP + WebSocket server (civetweb 1.15, Debian's libcivetweb-dev): serves the
// page (files embedded in the binary at build time: no internet needed) and carries JSON frames
// between browsers and a CockpitNode running under a LiveExecutor. I/O glue only: the logic is in
// the node.
//
// Threads: civetweb's workers receive (one per WebSocket connection) and hand each event (open,
// text message, close) to the executor's thread through a queue and an eventfd, so the node runs
// on one thread, like every node. The node's frames go to one sender thread that writes them to
// the sockets, so a slow browser never stalls the node (its gamepad deadman keeps running); the
// state frame is latest-value (a frame not yet sent is replaced by the next); replies, the hello
// and the mission frame are queued per client (at most kMaxQueued, further ones dropped and
// counted).
// Listens on ServerParams::listen (127.0.0.1:8088 by default: loopback only unless another
// address is configured); at most max_clients WebSocket connections; a WebSocket request whose
// Origin header names another host than its Host header is refused (a page from another site
// in the same browser cannot talk to the cockpit).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "cockpit/cockpit_config.hpp"
#include "cockpit/cockpit_node.hpp"
#include "runtime/live.hpp"

struct mg_context;
struct mg_connection;

namespace tiller::cockpit {

class CockpitServer {
 public:
  static constexpr std::size_t kMaxQueued = 64;
  // Starts listening; throws std::runtime_error naming the address when it cannot.
  CockpitServer(const ServerParams& p, CockpitNode& node, LiveExecutor& ex);
  ~CockpitServer();
  CockpitServer(const CockpitServer&) = delete;
  CockpitServer& operator=(const CockpitServer&) = delete;

  // http://ADDRESS:PORT/ as configured (0.0.0.0 shown as 127.0.0.1).
  const std::string& url() const { return url_; }

 private:
  struct Event {
    enum Kind { kOpen, kText, kClose } kind;
    int client;
    std::string text;
    TimeUs at = 0;  // when it arrived (the node is told this, as LCM messages their receive time)
  };
  struct Client {
    mg_connection* conn = nullptr;
    bool greeted = false;  // hello queued: state frames may follow
    std::deque<std::string> queue;
  };

  static int on_http(mg_connection* conn, void* self);
  static int on_ws_connect(const mg_connection* conn, void* self);
  static void on_ws_ready(mg_connection* conn, void* self);
  static int on_ws_data(mg_connection* conn, int bits, char* data, std::size_t len, void* self);
  static void on_ws_close(const mg_connection* conn, void* self);
  void push_event(Event e);
  void drain_events(TimeUs now);
  void sink(int client, const std::string& json);
  void sender_loop();

  CockpitNode& node_;
  LiveExecutor& ex_;
  int max_clients_;
  std::string url_;
  int event_fd_ = -1;
  mg_context* ctx_ = nullptr;

  std::mutex events_mutex_;
  std::deque<Event> events_;

  std::mutex write_mutex_;    // held while writing to sockets, and by on_ws_close
  std::mutex clients_mutex_;  // clients_, ids_, broadcast_, next_id_ (never held while writing)
  std::condition_variable wake_;
  std::map<int, Client> clients_;
  std::map<const mg_connection*, int> ids_;
  int next_id_ = 1;
  std::string broadcast_;
  bool broadcast_pending_ = false;
  bool stopping_ = false;
  std::int64_t dropped_ = 0;
  std::thread sender_;
};

}  // namespace tiller::cockpit
