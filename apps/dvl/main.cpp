// tiller-dvl: a Water Linked DVL-A50 over its TCP JSON protocol -> TILLER_DVL (bottom-track
// velocity in body FRD). The DVL absent or gone: said on stderr and in the heartbeat (FAULT),
// retried; the process keeps running.
#include <cstdio>

#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/dvl_link.hpp"
#include "sensors/dvl_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-dvl",
                       "Water Linked DVL-A50 (TCP JSON) -> bottom-track velocity on TILLER_DVL",
                       "config/sensors/dvl_a50.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::DvlParams p = sensors::load_dvl_file(args.config);
    sensors::DvlNode node(p);
    std::fprintf(stderr, "tiller-dvl: DVL at %s:%d, mounting roll %.1f pitch %.1f yaw %.1f deg\n",
                 p.host.c_str(), p.port, p.roll * 57.29577951308232, p.pitch * 57.29577951308232,
                 p.yaw * 57.29577951308232);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    sensors::DvlLink link(p, node, ex);
    link.service(wall_time_us());
    return ex.run();
  });
}
