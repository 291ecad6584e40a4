// tiller-teleop: reads a joystick (Linux js interface) and publishes the pilot's demands.
#include <unistd.h>

#include <cstdio>

#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "teleop/js_device.hpp"
#include "teleop/teleop_live.hpp"
#include "teleop/teleop_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-teleop",
      "joystick -> manual demand, manual velocity, mode and arm requests",
      "config/teleop/extreme3dpro_seed000.yaml",
      {{"device", "PATH",
        "joystick device, FIFO or file (default: the config's device, e.g. /dev/input/js0)", ""},
       {"station", "ID",
        "this operator station's id (default: the config's station, else the host name)", ""},
       {"name", "NAME", "the node's name (default teleop; a second station's teleop needs its own)",
        ""},
       {"replay", "", "take TILLER_JOYSTICK from LCM instead of a device", ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    TeleopParams p = load_teleop_file(args.config);
    if (!args.get("device").empty()) p.device_path = args.get("device");
    if (!args.get("station").empty()) p.station = args.get("station");
    if (!args.get("name").empty()) p.node_name = args.get("name");
    if (p.station.empty()) {
      char host[256] = {};
      p.station = gethostname(host, sizeof host - 1) == 0 && host[0] ? host : "teleop";
    }
    std::fprintf(stderr, "tiller-teleop: station %s\n", p.station.c_str());
    const bool replay = args.flag("replay");
    TeleopNode node(p, replay ? TeleopNode::Input::replay : TeleopNode::Input::device);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    if (replay) return ex.run();
    JsDevice device(p.device_path, p.device_name);
    JoystickPump pump(device, node, ex, p.reopen_period);
    return ex.run();
  });
}
