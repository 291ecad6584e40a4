// tiller-mavlink's parameters, as a ground station sees them (PARAM_REQUEST_LIST / READ / SET,
// MAV_PARAM_TYPE_REAL32): the bridge's own gains and limits, each with the bounds its config key
// has in mavlink/mavlink_config.cpp (the one table both use). A set outside the bounds, of an
// unknown name or a NaN is refused (the old value is sent back and a STATUSTEXT says why).
#pragma once

#include <array>
#include <cstddef>

namespace tiller::mavlink {

struct ParamSpec {
  const char* id;   // at most 16 characters (PARAM_VALUE.param_id)
  const char* key;  // the config key it comes from (docs/reference/configuration.md)
  double min, max;  // the key's bounds
  double fallback;  // the value when the config does not give one
  const char* units;
};

enum ParamIndex : std::size_t {
  kManGain,      // manual_control.gain: the stick's scale, [0, 1]
  kManDeadzone,  // manual_control.deadzone: fraction of full stick counted as centred
  kManTimeout,   // manual_control.timeout_s: no MANUAL_CONTROL for this long = neutral, invalid
  kManYawGain,   // manual_control.yaw_gain: the yaw stick's scale, [0, 1]
  kSysidMygcs,   // gcs_system_id: the one ground station obeyed
  kParamCount
};

inline constexpr std::array<ParamSpec, kParamCount> kParams = {{
    {"MAN_GAIN", "manual_control.gain", 0.0, 1.0, 1.0, "1"},
    {"MAN_DEADZONE", "manual_control.deadzone", 0.0, 0.5, 0.05, "1"},
    {"MAN_TIMEOUT", "manual_control.timeout_s", 0.05, 1.0, 0.5, "s"},
    {"MAN_YAW_GAIN", "manual_control.yaw_gain", 0.0, 1.0, 1.0, "1"},
    {"SYSID_MYGCS", "gcs_system_id", 1.0, 255.0, 255.0, ""},
}};

}  // namespace tiller::mavlink
