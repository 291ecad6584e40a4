// tiller-mixer: thrust allocation. Subscribes TILLER_MANUAL_DEMAND, TILLER_WRENCH_VELOCITY,
// TILLER_WRENCH_STATION, TILLER_ARBITRATION, TILLER_ARM_STATE; publishes
// TILLER_THRUSTER_COMMAND and TILLER_ALLOCATION_STATUS. See lib/mixer/mixer_node.hpp.
#include <iostream>

#include "mixer/mixer_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(
      argc, argv,
      {"tiller-mixer",
       "Allocates the active wrench (or the manual demand) onto the thrusters of a vehicle.",
       "config/mixer/seed001_rov6.yaml",
       {{"describe", "", "print the vehicle's allocation (groups, unactuated axes) and exit",
         ""}}});
  return app::guarded_main("tiller-mixer", [&] {
    MixerNode node(args.config);
    if (args.flag("describe")) {
      std::cout << node.allocator().describe() << "\n";
      return 0;
    }
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
