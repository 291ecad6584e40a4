// tiller-path-follower: the seed-004 command-velocity generator on LCM.
// TILLER_PATH + TILLER_ODOMETRY + TILLER_MODE -> TILLER_VELOCITY_SETPOINT, TILLER_PATH_PROGRESS,
// TILLER_STATION_TARGET (see lib/guidance/path_follower_node.hpp).
#include "core/config.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args =
      app::parse(argc, argv,
                 {"tiller-path-follower",
                  "Follows a path (TILLER_PATH): velocity setpoints for the velocity PID.",
                  "config/guidance/default.yaml",
                  {}});
  return app::guarded_main("tiller-path-follower", [&] {
    const auto root = config::Value::load_file(args.config);
    const auto params = guidance::load_follower_node_params(root);
    root.check_all_used();
    guidance::PathFollowerNode node(params);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
