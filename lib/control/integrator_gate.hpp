// When a controller's integrator may run, from the mixer's latest TILLER_THRUSTER_COMMAND (its
// safety gate, lib/safety/intent_gate.hpp, and the source it allocated). An integrator that runs
// while its wrench is not reaching the thrusters winds up (issue 12: the yaw integral reached its
// limit in 4 s while disarmed) and steps the thrust when the vehicle is armed and started.
//   no fresh command (no mixer, or it stopped)       -> freeze: keep the integral, do not add
//   gate DISARMED or WAIT_NEUTRAL (nothing started)  -> reset to zero: the next start (gate
//                                                       ACTIVE) begins from zero integral
//   gate INPUT_LOST                                  -> freeze (input back: carry on)
//   gate ACTIVE, another source allocated            -> freeze (not in control)
//   gate ACTIVE, this controller's source allocated  -> integrate
// Pure: the caller keeps the command and its freshness.
#pragma once

#include <cstdint>

#include <tiller/thruster_command_t.hpp>

namespace tiller::control {

enum class IntegratorRule { kIntegrate, kFreeze, kReset };

inline IntegratorRule integrator_rule(bool command_fresh, std::int8_t gate,
                                      std::int8_t command_source, std::int8_t own_source) {
  if (!command_fresh) return IntegratorRule::kFreeze;
  if (gate == thruster_command_t::GATE_DISARMED || gate == thruster_command_t::GATE_WAIT_NEUTRAL)
    return IntegratorRule::kReset;
  if (gate != thruster_command_t::GATE_ACTIVE || command_source != own_source)
    return IntegratorRule::kFreeze;
  return IntegratorRule::kIntegrate;
}

}  // namespace tiller::control
