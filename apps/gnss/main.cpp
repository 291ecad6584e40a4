// tiller-gnss: a GNSS receiver through gpsd (every receiver gpsd supports) -> TILLER_GNSS.
// gpsd absent or gone: said on stderr and in the heartbeat (FAULT), retried; keeps running.
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/gpsd_client.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-gnss", "GNSS fixes from gpsd -> TILLER_GNSS", "config/sensors/gnss_gpsd.yaml", {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::GnssParams p = sensors::load_gnss_file(args.config);
    sensors::GnssNode node(p);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    sensors::GpsdClient gpsd(p, node, ex);
    gpsd.connect(wall_time_us());
    return ex.run();
  });
}
