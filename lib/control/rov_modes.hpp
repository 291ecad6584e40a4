// The ROV pilot modes of tiller-rov-control (docs/flying.md, "ROV modes"): what each does with
// each axis of the body wrench [X Y Z K M N], and which axes it needs. Modes are
// controller_mode_t constants:
//   MANUAL_OPEN_LOOP  manual: the stick straight to the mixer (seed 000's open loop; the
//                     controller is not in the path)
//   STABILISE         roll and pitch held level, the twist commands the yaw rate, the rest
//                     pass-through; needs roll (K) or pitch (M)
//   DEPTH_HOLD        stabilise, and the depth held: the vertical stick commands a climb rate
//                     and releasing it holds the new depth; needs heave (Z)
//   HEADING_HOLD      stabilise with the heading held (the twist overrides, release holds the new
//                     heading); needs yaw (N)
//   RATE              acro: the sticks command body rates on roll, pitch and yaw (a released
//                     stick holds rate 0), translations pass-through; needs roll or pitch
//   SURFACE           rises at surface.speed_m_s until surface.depth_m (then heave is left
//                     alone), attitude level, yaw rate and translations from the pilot; needs
//                     heave
//   POSITION_HOLD     north, east, depth and heading held (each overridden by its stick), level;
//                     needs surge, sway, heave and yaw, and a valid position in the odometry
//   DEPTH_HEADING_HOLD  depth and heading held (each overridden by its stick), level,
//                     translations from the stick (centred: no translation thrust): where
//                     position hold falls back when its position is lost; needs heave and yaw
// Of the odometry every assisted mode needs the attitude and rates; only the modes that use the
// depth (depth hold, surface, position hold, depth and heading hold: uses_depth) need a valid
// depth, so heading hold, stabilise and rate fly on an estimate without one (a lost pressure
// sensor, or a layout without heave, such as the 4-thruster ROV). A held axis is overridden by its
// stick and holds the new value on release (control/ rov_axes.hpp). An axis the layout cannot
// actuate (Allocator::unactuated) is never controlled: kOff. A mode whose needs the layout does not
// meet is refused with a reason that names the axis. MANUAL_CLOSED_LOOP is the USVs' mode: refused
// here.
//   WAYPOINTING       a mission (autonomy: the mixer's gate waits for the operator's START; the
//                     stick is not in the path): surge and sway track the path follower's
//                     velocity setpoint (kRate), depth and heading are held on references the
//                     node moves toward the path's depth and the follower's heading (RovAxes::
//                     guide), level; at the end all four hold the station target. Needs surge,
//                     sway, heave and yaw, and a valid position
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "control/rov_axes.hpp"

namespace tiller::control {

struct ModePlan {
  std::array<AxisRole, 6> roles{};
  bool level = false;    // roll and pitch hold 0
  bool surface = false;  // heave rises at the surface speed, not from the stick
};

// "manual", "stabilise", "depth_hold", "heading_hold", "rate", "surface", "position_hold",
// "depth_heading_hold",
// "closed_loop", "waypointing"; "?" for an unknown constant.
const char* rov_mode_name(std::int8_t mode);
// The inverse; -1 when the name is none of them.
int rov_mode_from_name(const std::string& name);
// Human words for the status line ("depth hold").
const char* rov_mode_words(std::int8_t mode);

// Whether a plan uses the depth (its heave axis holds it, or it surfaces).
inline bool uses_depth(const ModePlan& p) {
  return p.roles[2] == AxisRole::kHold || p.surface;
}

// The plan of `mode` (not MANUAL_OPEN_LOOP) on a layout where actuated[a] says axis a has
// authority, with the odometry's position and depth valid or not. Returns true and fills
// `plan`, or false with the reason it is refused ("depth hold refused: seed000_rov4 cannot
// actuate heave (Z)", "depth hold refused: the odometry carries no valid depth") written into
// `why` (no allocation once `why` has room: the node reserves it).
bool plan_rov_mode(std::int8_t mode, const std::array<bool, 6>& actuated, bool position_valid,
                   bool depth_valid, const std::string& vehicle, ModePlan& plan, std::string& why);

}  // namespace tiller::control
