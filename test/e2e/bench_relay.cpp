// A bare LCM relay for the latency benchmark's baseline ("three bare LCM hops"): no Tiller code.
//   bench_relay fifo PATH OUT_CHANNEL URL   each read from the FIFO -> one 96-byte publish
//   bench_relay lcm IN_CHANNEL OUT_CHANNEL URL   each message received -> republished as is
// The FIFO variant stands where tiller-teleop stands (it reads the stick), so the baseline has
// the same shape as the Tiller chain: FIFO -> process -> LCM -> process -> LCM -> process -> LCM.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <cstring>
#include <string>

namespace {
struct Relay {
  lcm::LCM* l;
  std::string out;
  void on(const lcm::ReceiveBuffer* rb, const std::string&) {
    l->publish(out, rb->data, rb->data_size);
  }
};
}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: bench_relay fifo PATH OUT URL | bench_relay lcm IN OUT URL\n");
    return 2;
  }
  const std::string mode = argv[1];
  lcm::LCM l(argv[4]);
  if (!l.good()) return 1;
  if (mode == "lcm") {
    Relay r{&l, argv[3]};
    l.subscribe(argv[2], &Relay::on, &r);
    while (l.handle() == 0) {
    }
    return 0;
  }
  const int fd = ::open(argv[2], O_RDONLY);
  if (fd < 0) return 1;
  unsigned char buf[512];
  unsigned char msg[96] = {};
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, -1) < 0) continue;
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) return 0;
    std::memcpy(msg, buf, n < 8 ? static_cast<std::size_t>(n) : 8u);
    l.publish(argv[3], msg, sizeof msg);
  }
}
