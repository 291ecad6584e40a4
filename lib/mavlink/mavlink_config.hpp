// tiller-mavlink's config (config/mavlink/*.yaml; docs/reference/configuration.md "mavlink"):
// the vehicle's MAVLink identity, the ground station it obeys, signing, the transport, telemetry
// rates and the manual control mapping. Strict: unknown, missing or out-of-range keys stop the
// program naming the file, the key and what was expected.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <vector>
#include "core/config.hpp"
#include "core/time.hpp"

#include "mavlink/mavlink_gains.hpp"
#include "mavlink/mavlink_params.hpp"
#include "mavlink/signing.hpp"

namespace tiller::mavlink {

struct MavlinkParams {
  TimeUs period = 20000;          // tick, us (50 Hz)
  std::uint8_t system_id = 1;     // the vehicle's MAVLink system id
  std::uint8_t component_id = 1;  // MAV_COMP_ID_AUTOPILOT1
  bool submarine = false;         // HEARTBEAT type SUBMARINE (else SURFACE_BOAT)
  std::string station;            // arm_request_t / manual_demand_t station ("" = main's)
  std::array<double, kParamCount> params{};  // kParams' values (mavlink/mavlink_params.hpp)
  std::vector<GainParam> gains;          // the controllers' gains (control_config:), after kParams
  double z_centre = 500;                 // MANUAL_CONTROL.z at neutral heave (QGC: 500 of 0..1000)
  bool require_signed = false;           // drop unsigned frames (needs a secret)
  std::optional<Secret> secret;          // the signing secret (signing.*)
  bool secret_from_vehicle_key = false;  // signing.vehicle_key: main derives it (vehicle_secret)
  std::string secret_file;  // signing.key_file resolved ("": another source): SETUP_SIGNING saves
  TimeUs mission_retry = 1500000;  // re-request a missing mission item after this long
};

struct TransportParams {
  std::string udp_bind = "127.0.0.1:14551";  // ADDRESS:PORT the bridge listens on
  std::string udp_peer = "127.0.0.1:14550";  // where it sends until a station has spoken
  std::string serial_device;                 // "" = UDP; else e.g. /dev/ttyUSB0
  int serial_baud = 57600;
};

struct MavlinkConfig {
  MavlinkParams node;
  TransportParams transport;
};

// The MAVLink secret derived from the vehicle's LCM signing key (signing.vehicle_key: true): the
// 32-byte BLAKE2b of "tiller mavlink signing v1" keyed with it; `tiller-mavlink --print-secret`
// prints it in hex for the ground station.
Secret vehicle_secret(const std::array<std::uint8_t, 32>& vehicle_key);

// `dir` resolves signing.key_file relative to the config file.
MavlinkConfig load_mavlink(const config::Value& root, const std::string& dir);
MavlinkConfig load_mavlink_file(const std::string& path);

}  // namespace tiller::mavlink
