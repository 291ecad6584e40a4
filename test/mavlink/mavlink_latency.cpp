// mavlink_latency: the latency tiller-mavlink adds to the pilot's path, measured side by side in
// one run (prints figures; no assertion). Run it inside a private network namespace with a
// tiller-mavlink listening on 127.0.0.1:14551 (test/mavlink/mavlink_latency.sh does both):
//   LCM only:  this tool publishes a manual_demand_t and times its arrival back on
//              TILLER_MANUAL_DEMAND (one LCM hop, the hop every pilot source takes to the mixer);
//   MAVLink:   it sends a signed MANUAL_CONTROL to the bridge over UDP and times the bridge's
//              manual_demand_t on TILLER_MANUAL_DEMAND (UDP hop + the bridge + the same LCM hop).
// From TILLER_MANUAL_DEMAND on, both paths are the same (mixer, ESC), so the difference is what
// the bridge adds. Args: SECRET_HEX [SAMPLES]
#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include <tiller/manual_demand_t.hpp>

#include "mavlink/frame.hpp"

namespace {

std::int64_t now_us() {
  timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return ts.tv_sec * 1000000LL + ts.tv_nsec / 1000;
}

struct Rx {
  std::int64_t t = -1;
  bool bench = false;
  void on(const lcm::ReceiveBuffer* rb, const std::string&) {
    tiller::manual_demand_t m;
    if (m.decode(rb->data, 0, static_cast<int>(rb->data_size)) < 0) return;
    t = now_us();
    bench = m.station == "bench";
  }
};

double pct(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: mavlink_latency SECRET_HEX [SAMPLES]\n");
    return 2;
  }
  tiller::mavlink::Secret key{};
  for (std::size_t i = 0; i < key.size(); ++i)
    key[i] = static_cast<std::uint8_t>(std::stoi(std::string(argv[1] + 2 * i, 2), nullptr, 16));
  const int samples = argc > 2 ? std::atoi(argv[2]) : 2000;
  lcm::LCM lc("udpm://239.255.76.67:7667?ttl=0");
  if (!lc.good()) return 1;
  Rx rx;
  lc.subscribe("TILLER_MANUAL_DEMAND", &Rx::on, &rx);
  const int sock = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(14551);
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  tiller::mavlink::FrameWriter w(255, 190, key, 0);
  std::vector<double> a, b;
  for (int i = 0; i < samples; ++i) {
    tiller::manual_demand_t d{};
    d.utime = now_us();
    d.station = "bench";
    d.valid = false;
    rx.t = -1;
    const std::int64_t ta = now_us();
    lc.publish("TILLER_MANUAL_DEMAND", &d);
    double la = -1;
    while (now_us() - ta < 100000) {
      pollfd p{lc.getFileno(), POLLIN, 0};
      if (::poll(&p, 1, 100) > 0) lc.handle();
      if (rx.t >= 0 && rx.bench) {
        la = static_cast<double>(rx.t - ta);
        break;
      }
    }
    if (la >= 0) a.push_back(la);
    mavlink_message_t m;
    mavlink_msg_manual_control_pack_status(255, 190, w.status(), &m, 1, 0, 0, 500, 0, 0, 0, 0, 0, 0,
                                           0, 0, 0, 0, 0, 0);
    std::uint8_t buf[tiller::mavlink::kMaxFrame];
    const std::size_t n = w.finish(m, now_us(), buf);
    rx.t = -1;
    const std::int64_t tb = now_us();
    ::sendto(sock, buf, n, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    double lb = -1;
    while (now_us() - tb < 100000) {
      pollfd p{lc.getFileno(), POLLIN, 0};
      if (::poll(&p, 1, 100) > 0) lc.handle();
      if (rx.t >= 0 && !rx.bench) {
        lb = static_cast<double>(rx.t - tb);
        break;
      }
    }
    if (lb >= 0) b.push_back(lb);
  }
  if (a.empty() || b.empty()) {
    std::printf("mavlink_latency: no replies (LCM %zu, MAVLink %zu)\n", a.size(), b.size());
    return 1;
  }
  std::printf("path to TILLER_MANUAL_DEMAND  samples   p50 us   p99 us   max us\n");
  std::printf("LCM only                      %7zu %8.0f %8.0f %8.0f\n", a.size(), pct(a, 0.5),
              pct(a, 0.99), pct(a, 1.0));
  std::printf("MAVLink (UDP + tiller-mavlink) %6zu %8.0f %8.0f %8.0f\n", b.size(), pct(b, 0.5),
              pct(b, 0.99), pct(b, 1.0));
  std::printf("added by the bridge: p50 %.0f us, p99 %.0f us\n", pct(b, 0.5) - pct(a, 0.5),
              pct(b, 0.99) - pct(a, 0.99));
  return 0;
}
