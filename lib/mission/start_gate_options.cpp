#include "mission/start_gate_options.hpp"

namespace tiller::mission {

std::vector<app::Option> start_gate_options() {
  return {
      {"start-std-m", "M",
       "start gate: publish nothing until the estimate is valid with position 1-sigma <= M m", ""},
      {"start-settle-s", "S", "start gate: ... held for S s (default 0; alone: M = 0.5)", ""}};
}

StartGateParams start_gate_params(const app::Args& a) {
  StartGateParams g;
  const std::string m = a.get("start-std-m"), s = a.get("start-settle-s");
  g.enabled = !m.empty() || !s.empty();
  if (!m.empty())
    g.max_position_std_m =
        app::number_option(a, "start-std-m", 1e-3, 1e3, "a number of metres in [0.001, 1000]");
  if (!s.empty())
    g.settle_s =
        app::number_option(a, "start-settle-s", 0, 3600, "a number of seconds in [0, 3600]");
  return g;
}

}  // namespace tiller::mission
