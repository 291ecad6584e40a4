// tiller-mavlink: the MAVLink 2 bridge for QGroundControl and Cockpit (lib/mavlink; docs/
// ground-stations.md). UDP (or a serial telemetry radio) on one side, LCM on the other.
#include <unistd.h>

#include <cstdio>
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
      static const int fd =
          mavlink::open_serial(cfg.transport.serial_device, cfg.transport.serial_baud);
      node.set_sink([](const std::uint8_t* d, std::size_t n) {
        if (::write(fd, d, n) < 0) return;  // a full radio buffer drops the frame
      });
      ex.add_fd(fd, [&node](TimeUs now) {
        long n;
        while ((n = ::read(fd, buf, sizeof buf)) > 0)
          node.on_bytes(buf, static_cast<std::size_t>(n), false, now);
      });
      std::printf("tiller-mavlink: serial %s at %d baud\n", cfg.transport.serial_device.c_str(),
                  cfg.transport.serial_baud);
    }
    std::fflush(stdout);
    return ex.run();
  });
}
