// tiller-leak: leak probes on GPIO lines (Linux GPIO character device, libgpiod) -> TILLER_LEAK.
// A line that cannot be requested or read reads wet (fail safe), is said in the heartbeat
// (FAULT, probe, chip and line named) and asked for again; the process keeps running.
#include <cstdio>

#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "sensors/gpiod_inputs.hpp"
#include "sensors/leak_node.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  const app::Spec spec{"tiller-leak",
                       "leak probes on GPIO lines -> wet / dry per probe",
                       "config/sensors/leak_gpio.yaml",
                       {}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    const sensors::LeakParams p = sensors::load_leak_file(args.config);
    sensors::GpiodInputs gpio;
    sensors::LeakNode node(p, gpio);
    std::fprintf(stderr, "tiller-leak: %zu probes, %.0f Hz\n", p.probes.size(), p.rate_hz);
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
