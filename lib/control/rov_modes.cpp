#include "control/rov_modes.hpp"

#include <cstdio>

#include <tiller/controller_mode_t.hpp>

namespace tiller::control {

namespace {
constexpr AxisRole O = AxisRole::kOff, P = AxisRole::kPilot, R = AxisRole::kRate,
                   H = AxisRole::kHold;
constexpr const char* kAxisWords[6] = {"surge (X)", "sway (Y)",  "heave (Z)",
                                       "roll (K)",  "pitch (M)", "yaw (N)"};
struct Entry {
  std::int8_t mode;
  const char* name;
  const char* words;
};
constexpr Entry kModes[] = {
    {controller_mode_t::MANUAL_OPEN_LOOP, "manual", "manual"},
    {controller_mode_t::MANUAL_CLOSED_LOOP, "closed_loop", "closed-loop manual"},
    {controller_mode_t::WAYPOINTING, "waypointing", "waypointing"},
    {controller_mode_t::STABILISE, "stabilise", "stabilise"},
    {controller_mode_t::DEPTH_HOLD, "depth_hold", "depth hold"},
    {controller_mode_t::HEADING_HOLD, "heading_hold", "heading hold"},
    {controller_mode_t::RATE, "rate", "rate (acro)"},
    {controller_mode_t::SURFACE, "surface", "surface"},
    {controller_mode_t::POSITION_HOLD, "position_hold", "position hold"},
    {controller_mode_t::DEPTH_HEADING_HOLD, "depth_heading_hold", "depth and heading hold"},
};
}  // namespace

const char* rov_mode_name(std::int8_t mode) {
  for (const Entry& e : kModes)
    if (e.mode == mode) return e.name;
  return "?";
}

const char* rov_mode_words(std::int8_t mode) {
  for (const Entry& e : kModes)
    if (e.mode == mode) return e.words;
  return "?";
}

int rov_mode_from_name(const std::string& name) {
  for (const Entry& e : kModes)
    if (name == e.name) return e.mode;
  return -1;
}

bool plan_rov_mode(std::int8_t mode, const std::array<bool, 6>& actuated, bool position_valid,
                   bool depth_valid, const std::string& vehicle, ModePlan& plan, std::string& why) {
  char buf[200];
  auto refuse = [&](const char* text) {
    why.assign(text);
    return false;
  };
  // The first needed axis the layout lacks.
  auto lacks = [&](std::initializer_list<int> axes) {
    for (int a : axes)
      if (!actuated[static_cast<std::size_t>(a)]) return a;
    return -1;
  };
  const char* words = rov_mode_words(mode);
  ModePlan p;
  switch (mode) {
    case controller_mode_t::STABILISE:
      p = {{P, P, P, H, H, R}, true, false};
      break;
    case controller_mode_t::DEPTH_HOLD:
      p = {{P, P, H, H, H, R}, true, false};
      break;
    case controller_mode_t::HEADING_HOLD:
      p = {{P, P, P, H, H, H}, true, false};
      break;
    case controller_mode_t::RATE:
      p = {{P, P, P, R, R, R}, false, false};
      break;
    case controller_mode_t::SURFACE:
      p = {{P, P, R, H, H, R}, true, true};
      break;
    case controller_mode_t::POSITION_HOLD:
      p = {{H, H, H, H, H, H}, true, false};
      break;
    case controller_mode_t::DEPTH_HEADING_HOLD:
      p = {{P, P, H, H, H, H}, true, false};
      break;
    case controller_mode_t::WAYPOINTING:
      p = {{R, R, H, H, H, H}, true, false};
      break;
    case controller_mode_t::MANUAL_CLOSED_LOOP:
      std::snprintf(buf, sizeof buf,
                    "%s refused: a surface-vehicle mode; an ROV flies manual, stabilise, depth "
                    "hold, heading hold, rate, surface, position hold, depth and heading hold or "
                    "waypointing",
                    words);
      return refuse(buf);
    default:
      return refuse("unknown mode refused");
  }
  int missing = -1;
  if (mode == controller_mode_t::STABILISE || mode == controller_mode_t::RATE) {
    if (!actuated[3] && !actuated[4]) {
      std::snprintf(buf, sizeof buf, "%s refused: %s cannot actuate roll (K) or pitch (M)", words,
                    vehicle.c_str());
      return refuse(buf);
    }
  } else if (mode == controller_mode_t::DEPTH_HOLD || mode == controller_mode_t::SURFACE) {
    missing = lacks({2});
  } else if (mode == controller_mode_t::HEADING_HOLD) {
    missing = lacks({5});
  } else if (mode == controller_mode_t::DEPTH_HEADING_HOLD) {
    missing = lacks({2, 5});
  } else if (mode == controller_mode_t::POSITION_HOLD || mode == controller_mode_t::WAYPOINTING) {
    missing = lacks({0, 1, 2, 5});
  }
  if (missing >= 0) {
    std::snprintf(buf, sizeof buf, "%s refused: %s cannot actuate %s", words, vehicle.c_str(),
                  kAxisWords[missing]);
    return refuse(buf);
  }
  if (mode == controller_mode_t::POSITION_HOLD && !position_valid)
    return refuse("position hold refused: the odometry carries no valid position");
  if (mode == controller_mode_t::WAYPOINTING && !position_valid)
    return refuse("waypointing refused: the odometry carries no valid position");
  for (std::size_t a = 0; a < 6; ++a)
    if (!actuated[a]) p.roles[a] = AxisRole::kOff;
  if (uses_depth(p) && !depth_valid) {
    std::snprintf(buf, sizeof buf, "%s refused: the odometry carries no valid depth", words);
    return refuse(buf);
  }
  plan = p;
  why.clear();
  return true;
}

}  // namespace tiller::control
