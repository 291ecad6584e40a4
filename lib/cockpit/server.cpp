#include "cockpit/server.hpp"

#include <civetweb.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "cockpit/web_files.hpp"

namespace tiller::cockpit {

namespace {
constexpr int kOpText = 0x1;  // WebSocket opcodes (RFC 6455)
constexpr int kOpClose = 0x8;
constexpr std::size_t kMaxMessage = 1 << 20;  // a mission file up to 1 MiB
}  // namespace

CockpitServer::CockpitServer(const ServerParams& p, CockpitNode& node, LiveExecutor& ex)
    : node_(node), ex_(ex), max_clients_(p.max_clients) {
  event_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (event_fd_ < 0) throw std::runtime_error(std::string("eventfd: ") + std::strerror(errno));
  mg_init_library(0);
  const std::string threads = std::to_string(p.max_clients + 4);
  const char* options[] = {"listening_ports",      p.listen.c_str(),    "num_threads",
                           threads.c_str(),        "enable_keep_alive", "yes",
                           "websocket_timeout_ms", "3600000",           nullptr};
  mg_callbacks cb{};
  ctx_ = mg_start(&cb, this, options);
  if (ctx_ == nullptr) {
    ::close(event_fd_);
    throw std::runtime_error("cannot listen on " + p.listen +
                             " (in use? another tiller-cockpit running? set `listen:`)");
  }
  mg_set_request_handler(ctx_, "/", &CockpitServer::on_http, this);
  mg_set_websocket_handler(ctx_, "/ws", &CockpitServer::on_ws_connect, &CockpitServer::on_ws_ready,
                           &CockpitServer::on_ws_data, &CockpitServer::on_ws_close, this);
  std::string host = p.listen.substr(0, p.listen.rfind(':'));
  if (host == "0.0.0.0" || host.empty()) host = "127.0.0.1";
  url_ = "http://" + host + ":" + p.listen.substr(p.listen.rfind(':') + 1) + "/";
  node_.set_sink([this](int client, const std::string& json) { sink(client, json); });
  ex_.add_fd(event_fd_, [this](TimeUs now) { drain_events(now); });
  sender_ = std::thread([this] { sender_loop(); });
}

CockpitServer::~CockpitServer() {
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  sender_.join();
  mg_stop(ctx_);  // closes every connection (close handlers run, queue events nobody drains)
  node_.set_sink({});
  ex_.remove_fd(event_fd_);
  ::close(event_fd_);
}

int CockpitServer::on_http(mg_connection* conn, void* self) {
  (void)self;
  const mg_request_info* ri = mg_get_request_info(conn);
  const WebFile* f = find_web_file(ri->local_uri ? ri->local_uri : "/");
  if (f == nullptr || std::strcmp(ri->request_method, "GET") != 0) {
    mg_send_http_error(conn, 404, "%s", "not found");
    return 404;
  }
  mg_printf(conn,
            "HTTP/1.1 200 OK\r\nContent-Type: %s\r\nContent-Length: %zu\r\n"
            "Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n\r\n",
            f->mime, f->size);
  mg_write(conn, f->data, f->size);
  return 200;
}

int CockpitServer::on_ws_connect(const mg_connection* conn, void* vself) {
  auto* self = static_cast<CockpitServer*>(vself);
  // Same origin only: a page from another site in the operator's browser could otherwise read
  // the vehicle's state (it still could not command: no token).
  const char* origin = mg_get_header(conn, "Origin");
  const char* host = mg_get_header(conn, "Host");
  if (origin != nullptr && host != nullptr) {
    const std::string o(origin);
    if (o != std::string("http://") + host && o != std::string("https://") + host) return 1;
  }
  std::lock_guard<std::mutex> lock(self->clients_mutex_);
  return static_cast<int>(self->clients_.size()) >= self->max_clients_ ? 1 : 0;
}

void CockpitServer::on_ws_ready(mg_connection* conn, void* vself) {
  auto* self = static_cast<CockpitServer*>(vself);
  int id = 0;
  {
    std::lock_guard<std::mutex> lock(self->clients_mutex_);
    id = self->next_id_++;
    self->clients_[id].conn = conn;
    self->ids_[conn] = id;
  }
  self->push_event({Event::kOpen, id, {}});
}

int CockpitServer::on_ws_data(mg_connection* conn, int bits, char* data, std::size_t len,
                              void* vself) {
  auto* self = static_cast<CockpitServer*>(vself);
  const int op = bits & 0xf;
  if (op == kOpClose) return 0;
  if (op != kOpText || len > kMaxMessage) return 1;  // pings, binary: ignored
  int id = 0;
  {
    std::lock_guard<std::mutex> lock(self->clients_mutex_);
    const auto it = self->ids_.find(conn);
    if (it == self->ids_.end()) return 0;
    id = it->second;
  }
  self->push_event({Event::kText, id, std::string(data, len)});
  return 1;
}

void CockpitServer::on_ws_close(const mg_connection* conn, void* vself) {
  auto* self = static_cast<CockpitServer*>(vself);
  int id = 0;
  {
    // Waits for a write in progress: the connection is gone once this returns.
    std::lock_guard<std::mutex> write_lock(self->write_mutex_);
    std::lock_guard<std::mutex> lock(self->clients_mutex_);
    const auto it = self->ids_.find(conn);
    if (it == self->ids_.end()) return;
    id = it->second;
    self->ids_.erase(it);
    self->clients_.erase(id);
  }
  self->push_event({Event::kClose, id, {}});
}

void CockpitServer::push_event(Event e) {
  e.at = wall_time_us();
  {
    std::lock_guard<std::mutex> lock(events_mutex_);
    events_.push_back(std::move(e));
  }
  const std::uint64_t one = 1;
  (void)!::write(event_fd_, &one, sizeof one);
}

void CockpitServer::drain_events(TimeUs now) {
  (void)now;  // each event is told its own arrival time
  std::uint64_t n = 0;
  (void)!::read(event_fd_, &n, sizeof n);
  std::deque<Event> batch;
  {
    std::lock_guard<std::mutex> lock(events_mutex_);
    batch.swap(events_);
  }
  for (Event& e : batch) {
    switch (e.kind) {
      case Event::kOpen:
        node_.client_opened(e.client, e.at);
        {
          std::lock_guard<std::mutex> lock(clients_mutex_);
          const auto it = clients_.find(e.client);
          if (it != clients_.end()) it->second.greeted = true;
        }
        break;
      case Event::kText:
        node_.command(e.client, e.text, e.at);
        break;
      case Event::kClose:
        node_.client_closed(e.client, e.at);
        break;
    }
  }
}

void CockpitServer::sink(int client, const std::string& json) {
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    if (client == CockpitNode::kAllClients) {
      broadcast_ = json;  // latest value: an unsent frame is replaced
      broadcast_pending_ = true;
    } else if (client == CockpitNode::kEveryClient) {
      for (auto& [id, c] : clients_) {
        if (!c.greeted) continue;  // client_opened sends it after the hello
        if (c.queue.size() >= kMaxQueued) {
          ++dropped_;
          continue;
        }
        c.queue.push_back(json);
      }
    } else {
      const auto it = clients_.find(client);
      if (it == clients_.end()) return;
      if (it->second.queue.size() >= kMaxQueued) {
        ++dropped_;
        return;
      }
      it->second.queue.push_back(json);
    }
  }
  wake_.notify_one();
}

void CockpitServer::sender_loop() {
  struct Out {
    mg_connection* conn;
    std::string text;
  };
  std::vector<Out> out;
  std::string frame;
  while (true) {
    out.clear();
    {
      std::unique_lock<std::mutex> lock(clients_mutex_);
      wake_.wait(lock, [this] {
        if (stopping_ || broadcast_pending_) return true;
        for (const auto& c : clients_)
          if (!c.second.queue.empty()) return true;
        return false;
      });
      if (stopping_) return;
      for (auto& [id, c] : clients_) {
        for (auto& q : c.queue) out.push_back({c.conn, std::move(q)});
        c.queue.clear();
      }
      if (broadcast_pending_) {
        frame.swap(broadcast_);
        broadcast_pending_ = false;
        for (auto& [id, c] : clients_)
          if (c.greeted) out.push_back({c.conn, frame});
      }
    }
    // Written without clients_mutex_ (the node's thread never waits for a socket), under
    // write_mutex_, which on_ws_close takes before it forgets a connection.
    std::lock_guard<std::mutex> write_lock(write_mutex_);
    for (const Out& o : out) {
      {
        std::lock_guard<std::mutex> lock(clients_mutex_);
        if (ids_.find(o.conn) == ids_.end()) continue;  // closed meanwhile
      }
      mg_websocket_write(o.conn, kOpText, o.text.data(), o.text.size());
    }
  }
}

}  // namespace tiller::cockpit
