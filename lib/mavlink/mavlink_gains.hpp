// The controllers' tunable gains as tiller-mavlink parameters (MAV_PARAM_TYPE_REAL32), after the
// bridge's own (mavlink/mavlink_params.hpp): read from the control config the bridge's config
// names (`control_config:`, config/control/<vehicle>.yaml) by lib/control's own loaders, so the
// file is checked as the controllers check it:
//   velocity_pid (tiller-velocity-pid)  VP_<SURGE|SWAY|YAW>_<KDRAG|KDRAGQ|KERR|KI|ILIM|MAXOUT>,
//                                       VP_HEADING_KP, VP_MAX_YAW_RATE
//   station_keep (tiller-station-keep)  SK_<X|Y|YAW>_<KP|KI|KD|ILIM|MAXOUT>
//   rov_control (tiller-rov-control)    ROV_<SURGE|SWAY|HEAVE|ROLL|PITCH|YAW>_
//                                       <PILOT|KP|KI|KD|KIRATE|ILIM|MAXOUT>
// Units are the config key's (N per m/s, N per m, N m per rad, ...:
// docs/reference/configuration.md). Bounds are the loaders' (lib/control/control_config.cpp,
// rov_config.cpp): config::Range at_least(0) for the gains and limits, positive() for max_output
// and max_yaw_rate, [0, 1] for an ROV axis's pilot scale. What an accepted set does: it changes the
// bridge's copy only. The controllers read their config at start and have no channel for a new
// gain, so a set does not reach the running controller; the bridge says so in a STATUSTEXT and
// lists every changed gain as a config diff (gains_diff(), in the heartbeat's health text), to be
// written into the control file.
#pragma once

#include <string>
#include <vector>

namespace tiller::mavlink {

struct GainParam {
  std::string id;                // at most 16 characters
  std::string key;               // the control config's key, e.g. velocity_pid.surge.k_error
  double value = 0, loaded = 0;  // now, and as read from the file
  double min = 0, max = 0;       // the loader's range (inclusive)
};

// The gains of the control config `file` (velocity_pid and station_keep, or rov_control);
// throws config::Error as the controllers' loaders do.
std::vector<GainParam> load_gain_params(const std::string& file);

// The changed gains as "key: value" lines (value was loaded), "" when none changed.
std::string gains_diff(const std::vector<GainParam>& gains);

}  // namespace tiller::mavlink
