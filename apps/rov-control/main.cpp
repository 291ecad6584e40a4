// tiller-rov-control: the ROV's pilot modes and their 6-DOF controller (TILLER_ARBITRATION,
// TILLER_WRENCH_ROV; lib/control/rov_node.hpp). `--mode NAME` instead sends one mode request
// (TILLER_MODE, signed like every message) and exits: the command path for the modes.
// `--trust-position` takes odometry without a covariance as a valid position (the simulator's).
#include <tiller/controller_mode_t.hpp>

#include <iostream>
#include <vector>

#include "control/rov_config.hpp"
#include "control/rov_modes.hpp"
#include "control/rov_node.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const auto args = app::parse(
      argc, argv,
      {"tiller-rov-control",
       "The ROV's pilot modes (manual, stabilise, depth hold, heading hold, rate, surface, "
       "position hold, depth and heading hold) and their per-axis controller; or sends one mode "
       "request (--mode).",
       "config/control/seed001_rov6.yaml",
       {{"mode", "NAME",
         "send one mode request and exit: manual, stabilise, depth_hold, heading_hold, rate, "
         "surface, position_hold or depth_heading_hold",
         ""},
        {"trust-position", "",
         "odometry without a covariance carries a valid position (the simulator's is exact)",
         ""}}});
  return app::guarded_main("tiller-rov-control", [&] {
    const std::string name = args.get("mode");
    if (!name.empty()) {
      const int mode = control::rov_mode_from_name(name);
      if (mode < 0 || mode == controller_mode_t::MANUAL_CLOSED_LOOP ||
          mode == controller_mode_t::WAYPOINTING) {
        std::cerr << "tiller-rov-control: --mode: expected manual, stabilise, depth_hold, "
                     "heading_hold, rate, surface, position_hold or depth_heading_hold, got '"
                  << name << "'\n";
        return 2;
      }
      controller_mode_t m{};
      m.utime = wall_time_us();
      m.mode = static_cast<std::int8_t>(mode);
      m.source = "tiller-rov-control";
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
      m.encode(buf.data(), 0, static_cast<int>(buf.size()));
      LiveExecutor ex(args.lcm_url, args.auth);
      ex.publish_raw(channels::kMode, buf.data(), static_cast<int>(buf.size()));
      std::cout << "tiller-rov-control: sent mode " << name
                << " (the reply, accepted or refused, is on TILLER_ARBITRATION)\n";
      return 0;
    }
    control::RovControlParams p = control::load_rov_control_file(args.config);
    if (args.flag("trust-position")) p.require_position_covariance = false;
    control::RovControlNode node(p);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
