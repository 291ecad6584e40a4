// tiller-velocity-pid: the arbiter (TILLER_ARBITRATION) and the velocity PID
// (TILLER_WRENCH_VELOCITY, TILLER_PID_VELOCITY). See lib/control/velocity_pid_node.hpp.
#include "control/control_config.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(
      argc, argv,
      {"tiller-velocity-pid",
       "Chooses the wrench source (seed 004's choose_pid) and tracks velocity setpoints.",
       "config/control/otter.yaml",
       {}});
  return app::guarded_main("tiller-velocity-pid", [&] {
    const auto root = config::Value::load_file(args.config);
    control::VelocityPidNode node(control::load_velocity_pid_node_params(root));
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
