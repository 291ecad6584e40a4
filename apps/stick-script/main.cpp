// tiller-stick-script: a scripted pilot. Holds a joystick through the steps of a script
// (lib/teleop/stick_script.hpp), watching TILLER_ODOMETRY for depth and heading, and writes the
// stick as js_event records into the FIFO tiller-teleop reads as its device; prints each
// measured step's depth and heading errors at the end. Exit 0: every step done within its
// limits; 1: a step failed or an error was over its limit (docs/flying.md, "A scripted pilot").
#include <csignal>
#include <cstdio>
#include <cstring>

#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "teleop/js_writer.hpp"
#include "teleop/stick_script.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{
      "tiller-stick-script",
      "scripted pilot: a stick script -> js_event records into a FIFO",
      "config/pilot/rov_demo.yaml",
      {{"device", "PATH", "FIFO to write, made if absent (tiller-teleop's --device)",
        "/tmp/tiller-stick"}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    StickScriptNode node(load_stick_script_file(args.config));
    JsFifoWriter fifo(args.get("device"));
    std::signal(SIGPIPE, SIG_IGN);  // a reader gone shows as EPIPE from write()
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    std::fprintf(stderr, "tiller-stick-script: waiting for a reader on %s\n", fifo.path().c_str());
    if (!fifo.open_for_writing()) {
      std::fprintf(stderr, "tiller-stick-script: %s: %s\n", fifo.path().c_str(),
                   std::strerror(errno));
      return 1;
    }
    bool lost = false;
    node.on_stick([&](const joystick_state_t& s, TimeUs now) {
      if (!fifo.write(s, static_cast<std::uint32_t>(now / 1000))) {
        std::fprintf(stderr, "tiller-stick-script: %s: %s\n", fifo.path().c_str(),
                     std::strerror(errno));
        lost = true;
        ex.stop();
      }
      if (node.done()) ex.stop();
    });
    const int rc = ex.run();
    fifo.close();  // an unplug for the teleop: neutral at once
    std::printf("%s", node.report().c_str());
    std::fflush(stdout);
    if (rc != 0) return rc;
    return node.done() && !node.failed() && !lost ? 0 : 1;
  });
}
