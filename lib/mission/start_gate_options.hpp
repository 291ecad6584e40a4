// The start gate's command-line flags (mission/start_gate.hpp), one definition for tiller-mission
// and tiller-run:
//   --start-std-m M      wait for a valid estimate with horizontal position 1-sigma <= M m
//                        (the whole string a number in [0.001, 1000])
//   --start-settle-s S   ... held for S s (in [0, 3600]; default 0; alone: M = 0.5)
// Either flag enables the gate; neither leaves it off. A bad value throws std::runtime_error
// "--NAME: expected E, got 'V'" (the programs exit 2 with it).
#pragma once

#include <vector>

#include "mission/start_gate.hpp"
#include "runtime/app.hpp"

namespace tiller::mission {

std::vector<app::Option> start_gate_options();
StartGateParams start_gate_params(const app::Args& a);

}  // namespace tiller::mission
