// tiller-failsafe: the failsafes that need sensors (battery, leak, GNSS lost, geofence, depth
// limit) -> TILLER_VEHICLE_STATUS, and disarm requests (docs/safety.md, "Failsafes").
#include <cstdio>

#include "failsafe/failsafe_config.hpp"
#include "failsafe/failsafe_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-failsafe",
                       "battery, leak, GNSS, geofence and depth failsafes -> vehicle status",
                       "config/failsafe/otter.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const failsafe::FailsafeNodeParams p = failsafe::load_failsafe_file(args.config);
    failsafe::FailsafeNode node(p);
    const failsafe::MonitorParams& m = p.monitor;
    std::fprintf(stderr, "tiller-failsafe: battery %s, leak %s, gnss %s, geofence %s, depth %s\n",
                 m.battery.enabled ? "on" : "off", m.leak.enabled ? "on" : "off",
                 m.gnss.enabled ? "on" : "off", m.geofence.enabled ? "on" : "off",
                 m.depth.enabled ? "on" : "off");
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
