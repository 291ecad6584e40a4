// tiller-esc: the ESC bus driver. Thruster commands in, throttle/pulses out on the configured
// bus (BlueESC/tgy I2C, PCA9685 PWM, sim or dry-run); the one authority on arming.
// SIGINT/SIGTERM: neutral to every ESC, then exit.
#include <cstdio>

#include "auth/key.hpp"
#include "esc/esc_node.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

int main(int argc, char** argv) {
  using namespace tiller;
  return app::guarded_main("tiller-esc", [&] {
    const app::Args args = app::parse(
        argc, argv,
        {"tiller-esc",
         "ESC bus driver: thruster commands -> ESCs (I2C tgy, PCA9685 PWM, sim, dry-run); the one\n"
         "authority on arming. SIGINT/SIGTERM: neutral to every ESC, then exit.",
         "config/esc/seed000_sim.yaml",
         {}});
    EscNode node(args.config);
    // A new nonce per start: an arm request captured before this start names another one.
    node.set_boot_nonce(auth::random_nonce());
    const auto& b = node.backend();
    std::fprintf(stderr, "tiller-esc: %s on %s, %zu ESCs, %.0f Hz, command timeout %lld ms\n",
                 b.label().c_str(), b.bus().c_str(), b.size(), node.params().rate_hz,
                 static_cast<long long>(node.params().command_timeout_us / 1000));
    const esc::StartReport rep = node.start(wall_time_us());
    if (!rep.all_present) {
      std::fputs(rep.message.c_str(), stderr);
      if (node.params().missing_esc == esc::MissingEscPolicy::kRefuse) {
        node.shutdown(wall_time_us());  // neutral to the ESCs that did answer
        std::fputs(
            "tiller-esc: refusing to start (missing_esc: refuse); fix the wiring or "
            "set missing_esc: degraded\n",
            stderr);
        return 2;
      }
      std::fputs(
          "tiller-esc: running degraded (missing_esc: degraded); missing ESCs are "
          "retried every cycle\n",
          stderr);
    }
    LiveExecutor ex(args.lcm_url, args.auth);
    ex.add(node);
    return ex.run();
  });
}
