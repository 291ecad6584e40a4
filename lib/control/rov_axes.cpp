#include "control/rov_axes.hpp"

#include <algorithm>
#include <cmath>

#include "core/angles.hpp"

namespace tiller::control {

namespace {
constexpr int kX = 0, kY = 1, kZ = 2, kK = 3, kM = 4, kN = 5;
bool controlled(AxisRole r) {
  return r == AxisRole::kRate || r == AxisRole::kHold;
}
}  // namespace

RovAxes::RovAxes(const std::array<RovGains, 6>& gains, const std::array<double, 6>& max_plus,
                 const std::array<double, 6>& max_minus)
    : g_(gains), max_plus_(max_plus), max_minus_(max_minus) {}

void RovAxes::set_roles(const std::array<AxisRole, 6>& roles, bool level) {
  level_ = level;
  for (std::size_t a = 0; a < 6; ++a) {
    Axis& x = ax_[a];
    const AxisRole r = roles[a];
    if (r == x.role) continue;
    if (!controlled(r) || !controlled(x.role)) x.i = 0;  // from / to pass-through or off
    if (r == AxisRole::kHold) {
      // Enter by braking: the value is captured once the axis has slowed down (a level
      // attitude is held at once).
      x.holding = level && (a == kK || a == kM);
      x.target = 0;
      x.since_release = 0;
    } else {
      x.holding = false;
    }
    x.role = r;
  }
}

double RovAxes::value(int axis, const RovState& s) {
  switch (axis) {
    case kX:
      return s.north;
    case kY:
      return s.east;
    case kZ:
      return s.depth;
    case kK:
      return s.roll;
    case kM:
      return s.pitch;
    default:
      return s.yaw;
  }
}

double RovAxes::rate(int axis, const RovState& s) {
  if (axis == kZ) {
    // d(depth)/dt: the NED down component of the body velocity.
    const double sf = std::sin(s.roll), cf = std::cos(s.roll);
    const double st = std::sin(s.pitch), ct = std::cos(s.pitch);
    return -st * s.nu[0] + ct * sf * s.nu[1] + ct * cf * s.nu[2];
  }
  return s.nu[static_cast<std::size_t>(axis)];
}

double RovAxes::law(int a, double e, double v_sp, double v, bool hold, double dt,
                    IntegratorRule rule, bool reduced) {
  const RovGains& g = g_[static_cast<std::size_t>(a)];
  Axis& x = ax_[static_cast<std::size_t>(a)];
  // A stick's roll or pitch rate stops at max_angle: the setpoint is limited to what the hold
  // law would ask for to stay at the limit (kp / kd per rad of room left), so it slows to 0
  // there rather than switching off (which would chatter).
  if (!hold && (a == kK || a == kM) && g.max_angle > 0 && g.kd > 0) {
    const double angle = a == kK ? angle_now_[0] : angle_now_[1];
    const double k = g.kp / g.kd;
    v_sp = std::clamp(v_sp, -k * std::max(g.max_angle + angle, 0.0),
                      k * std::max(g.max_angle - angle, 0.0));
  }
  if (rule == IntegratorRule::kReset) x.i = 0;
  const double p = hold ? g.kp * e - g.kd * v : g.kd * (v_sp - v);
  if (rule == IntegratorRule::kIntegrate && dt > 0) {
    const double di = (hold ? g.ki * e : g.ki_rate * (v_sp - v)) * dt;
    const double before = p + x.i;
    // Anti-windup: no further growth into a saturation (the mixer's or this axis' own limit).
    const bool saturated = reduced || std::fabs(before) >= g.max_output;
    if (!(saturated && di * before > 0)) x.i = std::clamp(x.i + di, -g.i_limit, g.i_limit);
  }
  return std::clamp(p + x.i, -g.max_output, g.max_output);
}

std::array<double, 6> RovAxes::step(const RovState& s, const std::array<double, 6>& stick,
                                    double dt, IntegratorRule rule,
                                    const std::array<bool, 6>& reduced) {
  std::array<double, 6> out{};
  angle_now_ = {s.roll, s.pitch};
  const bool reset = rule == IntegratorRule::kReset;
  // A reset (disarmed, waiting for the start) makes every hold follow the vehicle.
  if (reset) {
    for (int a = 0; a < 6; ++a) {
      Axis& x = ax_[static_cast<std::size_t>(a)];
      if (x.role != AxisRole::kHold) continue;
      x.holding = true;
      x.since_release = 0;
      x.target = level_ && (a == kK || a == kM) ? 0.0 : value(a, s);
    }
  }
  const double cy = std::cos(s.yaw), sy = std::sin(s.yaw);

  // X and Y hold the NED position together.
  if (ax_[kX].role == AxisRole::kHold && ax_[kY].role == AxisRole::kHold) {
    Axis& x = ax_[kX];
    Axis& y = ax_[kY];
    const bool moved = stick[kX] != 0.0 || stick[kY] != 0.0;
    if (moved) {
      x.holding = y.holding = false;
      x.since_release = y.since_release = 0;
    } else if (!x.holding) {
      x.since_release += dt;
      const bool slow =
          std::fabs(s.nu[kX]) <= g_[kX].capture_rate && std::fabs(s.nu[kY]) <= g_[kY].capture_rate;
      if (slow || x.since_release >= g_[kX].capture_s) {
        x.holding = y.holding = true;
        x.target = s.north;
        y.target = s.east;
      }
    }
    double ex = 0, ey = 0;
    if (x.holding) {
      const double en = x.target - s.north, ee = y.target - s.east;
      ex = cy * en + sy * ee;
      ey = -sy * en + cy * ee;
    }
    // The integral is kept in NED (what it holds against, a current, does not turn with the
    // vehicle): into the body frame for the law, back after it.
    x.i = cy * i_ne_[0] + sy * i_ne_[1];
    y.i = -sy * i_ne_[0] + cy * i_ne_[1];
    for (int a : {kX, kY}) {
      const double e = a == kX ? ex : ey;
      const double sp =
          x.holding ? 0.0
                    : stick[static_cast<std::size_t>(a)] * g_[static_cast<std::size_t>(a)].max_rate;
      out[static_cast<std::size_t>(a)] = law(a, e, sp, s.nu[static_cast<std::size_t>(a)], x.holding,
                                             dt, rule, reduced[static_cast<std::size_t>(a)]);
    }
    i_ne_ = {cy * x.i - sy * y.i, sy * x.i + cy * y.i};
  } else {
    i_ne_ = {0, 0};
  }

  for (int a = 0; a < 6; ++a) {
    const auto i = static_cast<std::size_t>(a);
    Axis& x = ax_[i];
    const RovGains& g = g_[i];
    if ((a == kX || a == kY) && ax_[kX].role == AxisRole::kHold && ax_[kY].role == AxisRole::kHold)
      continue;  // done above
    double o = 0;
    switch (x.role) {
      case AxisRole::kOff:
        break;
      case AxisRole::kPilot:
        o = stick[i] * g.pilot * (stick[i] > 0 ? max_plus_[i] : max_minus_[i]);
        break;
      case AxisRole::kRate:
        o = law(a, 0, stick[i] * g.max_rate, rate(a, s), false, dt, rule, reduced[i]);
        break;
      case AxisRole::kHold: {
        const double v = rate(a, s);
        if (stick[i] != 0.0) {
          x.holding = false;  // the pilot overrides
          x.since_release = 0;
        } else if (!x.holding) {
          x.since_release += dt;
          if (std::fabs(v) <= g.capture_rate || x.since_release >= g.capture_s) {
            x.holding = true;
            x.target = value(a, s);
          }
        }
        const double e =
            x.holding ? (a == kN ? angle_diff(x.target, s.yaw) : x.target - value(a, s)) : 0.0;
        o = law(a, e, x.holding ? 0.0 : stick[i] * g.max_rate, v, x.holding, dt, rule, reduced[i]);
        break;
      }
    }
    if (a == kZ && controlled(x.role)) {
      // A force along NED down, in the body frame: R^T [0 0 F].
      vertical_ = o;
      const double sf = std::sin(s.roll), cf = std::cos(s.roll);
      const double st = std::sin(s.pitch), ct = std::cos(s.pitch);
      out[kX] += -st * o;
      out[kY] += ct * sf * o;
      out[kZ] += ct * cf * o;
    } else {
      if (a == kZ) vertical_ = 0;
      out[i] += o;
    }
  }
  return out;
}

}  // namespace tiller::control
