// tiller-cockpit's config (config/cockpit/*.yaml): the page server and the node behind it.
//
//   listen: 127.0.0.1:8088     # address:port of the HTTP + WebSocket server; loopback unless
//                              # another address is written here (e.g. 0.0.0.0:8088)
//   token_file: keys/cockpit.token   # the command token (made at first start, mode 0600)
//   token: ""                  # or the token itself (then token_file is not used)
//   rate_hz: 20                # state frames to the page per second (latest value per channel)
//   max_clients: 8             # WebSocket connections at once; one more is refused
//   processes: [sim, esc, mixer]    # heartbeats shown; each silent > silent_after_s is red
//   silent_after_s: 3
//   path_repeat_s: 1           # a path loaded from the page is re-sent this often (same id)
//   gamepad:                   # the page's gamepad (browser Gamepad API, "standard" mapping)
//     timeout_s: 0.5           # no gamepad message for this long: neutral, invalid demand
//     gain: 1.0                # [0, 1], scales every axis
//     axes:                    # like tiller-teleop's: gamepad axis index -> DOF
//       - {axis: 1, dof: surge, sign: -1, deadzone: 0.1, expo: 0.3, gain: 1.0}
//   thruster_test:             # the page's thruster test (cockpit/thruster_test.hpp)
//     max_command: 0.1         # [0, 0.3], the largest |command| the page may ask (0: no test);
//                              # the mixer's own thruster_test.max_command also applies
//     timeout_s: 0.5           # a held button is repeated every 0.1 s; silent this long: ended
#pragma once

#include <array>
#include <string>
#include <vector>

#include "cockpit/thruster_test.hpp"
#include "core/config.hpp"
#include "core/time.hpp"
#include "mission/start_gate.hpp"

namespace tiller::cockpit {

struct GamepadAxis {
  int axis = 0;  // index into the Gamepad API's axes[], 0..15
  int dof = 0;   // 0..5: [X Y Z K M N]
  double sign = 1, deadzone = 0.1, expo = 0.0, gain = 1.0;
};

struct CockpitParams {
  TimeUs period = from_hz(20);
  // This operator station's id on arm requests and the page's manual demand (docs/safety.md:
  // one station in control). Empty in the file: tiller-cockpit uses "cockpit@<host name>".
  std::string station;
  std::vector<std::string> processes;  // node names whose heartbeats the page shows
  TimeUs silent_after = 3'000'000;
  TimeUs path_repeat = 1'000'000;
  TimeUs gamepad_timeout = 500'000;
  double gamepad_gain = 1.0;
  std::vector<GamepadAxis> axes;
  ThrusterTestParams thruster_test;
  // start_gate: {max_position_std_m, settle_s}: a mission "start" is refused until the estimate
  // is good (mission/start_gate.hpp, as tiller-mission --start-std-m); absent: not checked.
  mission::StartGateParams start_gate;
};

struct ServerParams {
  std::string listen = "127.0.0.1:8088";
  std::string token_file = "keys/cockpit.token";
  std::string token;  // given in the config: token_file is not used
  int max_clients = 8;
};

struct CockpitConfig {
  CockpitParams node;
  ServerParams server;
};

CockpitConfig load_cockpit(const config::Value& root);
CockpitConfig load_cockpit_file(const std::string& path);
// "a,b,c" -> {"a", "b", "c"} (empty items dropped).
std::vector<std::string> split_list(const std::string& s);

}  // namespace tiller::cockpit
