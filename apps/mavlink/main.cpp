// tiller-mavlink: the MAVLink 2 bridge for QGroundControl and Cockpit (lib/mavlink; docs/
// ground-stations.md). UDP (or a serial telemetry radio) on one side, LCM on the other.
#include <sys/timerfd.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <stdexcept>

#include "auth/key.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mavlink/mavlink_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "udp_link.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-mavlink",
      "MAVLink 2 bridge: QGroundControl / Cockpit see, plan and drive the vehicle over UDP or "
      "serial",
      "config/mavlink/usv_sim.yaml",
      {{"listen", "ADDRESS:PORT", "override the config's udp.bind", ""},
       {"peer", "ADDRESS:PORT", "override the config's udp.peer (the station's port)", ""},
       {"print-secret", "", "print the signing secret (64 hex digits) for the ground station, exit",
        ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    mavlink::MavlinkConfig cfg = mavlink::load_mavlink_file(args.config);
    if (!args.get("listen").empty()) cfg.transport.udp_bind = args.get("listen");
    if (!args.get("peer").empty()) cfg.transport.udp_peer = args.get("peer");
    if (cfg.node.secret_from_vehicle_key) {
      if (!args.auth.key)
        throw std::runtime_error(args.config +
                                 ": signing.vehicle_key needs the vehicle's key (--key-file FILE "
                                 "or TILLER_KEY_FILE)");
      cfg.node.secret = mavlink::vehicle_secret(args.auth.key->bytes);
    }
    if (args.flag("print-secret")) {
      if (!cfg.node.secret) throw std::runtime_error(args.config + ": no signing: section");
      for (std::uint8_t b : *cfg.node.secret) std::printf("%02x", b);
      std::printf("\n");
      return 0;
    }
    if (cfg.node.station.empty()) {
      char host[256] = {};
      cfg.node.station =
          std::string("mavlink@") + (gethostname(host, sizeof host - 1) == 0 ? host : "");
    }
    mavlink::MavlinkNode node(cfg.node);
    if (!cfg.node.secret_file.empty()) {  // SETUP_SIGNING's new secret into signing.key_file
      const std::string file = cfg.node.secret_file;
      node.set_key_sink([file](const mavlink::Secret& s) {
        try {
          auth::Key k;
          k.bytes = s;
          k.id = auth::key_id(s);
          auth::write_key_file(file, k, true);
          std::fprintf(stderr, "tiller-mavlink: SETUP_SIGNING: new secret saved to %s\n",
                       file.c_str());
          return true;
        } catch (const std::exception& e) {
          std::fprintf(stderr, "tiller-mavlink: SETUP_SIGNING: not saved: %s\n", e.what());
          return false;
        }
      });
    }
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    static std::uint8_t buf[65536];
    if (cfg.transport.serial_device.empty()) {
      static mavlink::UdpLink udp(cfg.transport.udp_bind, cfg.transport.udp_peer);
      node.set_sink([](const std::uint8_t* d, std::size_t n) { udp.send(d, n, wall_time_us()); });
      ex.add_fd(udp.fd(), [&node](TimeUs now) {
        long n;
        while ((n = udp.receive(buf, sizeof buf, now)) >= 0)
          node.on_bytes(buf, static_cast<std::size_t>(n), true, now);
      });
      std::printf("tiller-mavlink: UDP %s, station port %s%s\n", cfg.transport.udp_bind.c_str(),
                  cfg.transport.udp_peer.c_str(),
                  cfg.node.require_signed ? ", signed frames only" : "");
    } else {
      // The radio: read when readable; a timer (10 Hz) writes what a full port left queued and,
      // while the port is lost, tries its path again every second. `watched` is the descriptor
      // the executor polls, dropped as soon as the link closes it (a closed fd in poll() would
      // spin).
      static mavlink::SerialLink serial(cfg.transport.serial_device, cfg.transport.serial_baud);
      static int watched = -1;
      static std::function<void()> watch;
      static const auto unwatch_if_lost = [&ex] {
        if (watched >= 0 && serial.fd() != watched) {
          ex.remove_fd(watched);
          watched = -1;
        }
      };
      watch = [&ex, &node] {
        unwatch_if_lost();
        if (watched >= 0 || serial.fd() < 0) return;
        watched = serial.fd();
        ex.add_fd(watched, [&node](TimeUs now) {
          long n;
          while ((n = serial.receive(buf, sizeof buf)) > 0)
            node.on_bytes(buf, static_cast<std::size_t>(n), false, now);
          unwatch_if_lost();
        });
      };
      node.set_sink([](const std::uint8_t* d, std::size_t n) {
        serial.send(d, n);
        unwatch_if_lost();
      });
      watch();
      static const int timer = ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
      if (timer < 0) throw std::runtime_error("timerfd_create failed");
      const itimerspec every{{0, 100'000'000}, {0, 100'000'000}};
      ::timerfd_settime(timer, 0, &every, nullptr);
      ex.add_fd(timer, [&node](TimeUs now) {
        std::uint64_t expirations;
        if (::read(timer, &expirations, sizeof expirations) < 0) return;
        static TimeUs last_try = 0;
        serial.flush();
        node.set_link_frames_dropped(serial.frames_dropped());
        if (serial.fd() < 0 && now - last_try >= kUsPerSecond) {
          last_try = now;
          serial.reopen();
        }
        watch();
      });
      std::printf("tiller-mavlink: serial %s at %d baud\n", cfg.transport.serial_device.c_str(),
                  cfg.transport.serial_baud);
    }
    std::fflush(stdout);
    return ex.run();
  });
}
