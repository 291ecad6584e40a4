// tiller-station-keep: the last-meter station-keeping PID (TILLER_WRENCH_STATION,
// TILLER_PID_STATION). See lib/control/station_keep_node.hpp.
#include "control/control_config.hpp"
#include "control/station_keep_node.hpp"
#include "core/config.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(argc, argv,
                               {"tiller-station-keep",
                                "Holds the vehicle on the station target (TILLER_STATION_TARGET).",
                                "config/control/otter.yaml",
                                {}});
  return app::guarded_main("tiller-station-keep", [&] {
    const auto root = config::Value::load_file(args.config);
    control::StationKeepNode node(control::load_station_keep_node_params(root));
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
