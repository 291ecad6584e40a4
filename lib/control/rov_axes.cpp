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
// While braking the integral may move only from where it was when the brake began toward
// where it was when the axis last held (its estimate of the disturbances: buoyancy, a current's
// moment), not past it: it sheds what it carried for the motion (drag at speed), but does not
// wind on the brake's large, brief rate error, which the hold after the capture would then carry
// and push the vehicle back with (a 5 deg swing back after a 1.4 rad/s turn braked).
double brake_limited(double i, double at_brake, double at_hold) {
  return std::clamp(i, std::min(at_brake, at_hold), std::max(at_brake, at_hold));
}
// sp moved toward goal by at most max_accel * dt (max_accel 0: at once).
double slew(double sp, double goal, double max_accel, double dt) {
  if (max_accel <= 0) return goal;
  const double d = max_accel * dt;
  return sp + std::clamp(goal - sp, -d, d);
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
    if (!controlled(r) || !controlled(x.role)) {
      x.i = 0;           // from / to pass-through or off
      x.sp_set = false;  // the setpoint starts from the measured rate
    }
    x.braking = false;
    x.i_hold = x.i;
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

void RovAxes::guide(int axis, double target, double rate) {
  Axis& x = ax_[static_cast<std::size_t>(axis)];
  if (x.role != AxisRole::kHold) return;
  x.holding = true;
  x.braking = false;
  x.since_release = 0;
  x.target = target;
  x.ff = rate;
  x.sp = 0;
  x.sp_set = true;
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

double RovAxes::angle_limited(int a, double v_sp) const {
  const RovGains& g = g_[static_cast<std::size_t>(a)];
  if ((a != kK && a != kM) || g.max_angle <= 0 || g.kd <= 0) return v_sp;
  const double angle = a == kK ? angle_now_[0] : angle_now_[1];
  const double k = g.kp / g.kd;
  return std::clamp(v_sp, -k * std::max(g.max_angle + angle, 0.0),
                    k * std::max(g.max_angle - angle, 0.0));
}

double RovAxes::error(int a, const RovState& s, double target) {
  return a == kN ? angle_diff(target, s.yaw) : target - value(a, s);
}

double RovAxes::law(int a, double e, double v_sp, double v, bool hold, double dt,
                    IntegratorRule rule, bool reduced) {
  const RovGains& g = g_[static_cast<std::size_t>(a)];
  Axis& x = ax_[static_cast<std::size_t>(a)];
  // A stick's roll or pitch rate stops at max_angle: the setpoint is limited to what the hold
  // law would ask for to stay at the limit (kp / kd per rad of room left), so it slows to 0
  // there rather than switching off (which would chatter).
  if (!hold) v_sp = angle_limited(a, v_sp);
  if (rule == IntegratorRule::kReset) x.i = 0;
  const double p = hold ? g.kp * e + g.kd * (v_sp - v) : g.kd * (v_sp - v);
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
      x.braking = false;
      x.i_hold = 0;
      x.since_release = 0;
      x.target = level_ && (a == kK || a == kM) ? 0.0 : value(a, s);
      x.sp = 0;
      x.sp_set = true;
    }
  }
  // X and Y hold the NED position together. Coming from their rate laws (waypointing's transit
  // to its station hold), their body integrals (a current) carry over, turned into NED.
  const bool xy = ax_[kX].role == AxisRole::kHold && ax_[kY].role == AxisRole::kHold;
  if (xy && !xy_held_) {
    const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
    i_ne_ = {c * ax_[kX].i - sn * ax_[kY].i, sn * ax_[kX].i + c * ax_[kY].i};
    i_ne_hold_ = i_ne_;
  }
  xy_held_ = xy;
  if (xy)
    step_xy(s, stick, dt, rule, reduced, out);
  else
    i_ne_ = {0, 0};

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
      case AxisRole::kRate: {
        const double v = rate(a, s);
        if (!x.sp_set) x.sp = v, x.sp_set = true;
        x.sp =
            angle_limited(a, slew(x.sp, angle_limited(a, stick[i] * g.max_rate), g.max_accel, dt));
        o = law(a, 0, x.sp, v, false, dt, rule, reduced[i]);
        break;
      }
      case AxisRole::kHold: {
        const double v = rate(a, s);
        if (!x.sp_set) x.sp = x.holding ? 0.0 : v, x.sp_set = true;
        if (stick[i] != 0.0) {
          // The pilot overrides: a rate law on the stick's rate.
          x.holding = x.braking = false;
          x.since_release = 0;
          x.sp = angle_limited(
              a, slew(x.sp, angle_limited(a, stick[i] * g.max_rate), g.max_accel, dt));
          o = law(a, 0, x.sp, v, false, dt, rule, reduced[i]);
        } else if (x.holding) {
          x.sp = 0;
          o = law(a, error(a, s, x.target), x.ff, v, true, dt, rule, reduced[i]);
          x.i_hold = x.i;
        } else {
          // Released (or entered while moving): brake, the setpoint ramping to 0 at max_accel
          // (at once without it); hold the value where the vehicle is once the setpoint is 0
          // and the rate under capture_rate, or capture_s after the setpoint reached 0.
          x.sp = slew(x.sp, 0, g.max_accel, dt);
          if (x.sp == 0.0) {
            x.since_release += dt;
            if (std::fabs(v) <= g.capture_rate || x.since_release >= g.capture_s) {
              x.holding = true;
              x.target = value(a, s);
            }
          }
          if (!x.braking) x.braking = true, x.i_brake = x.i;
          o = law(a, x.holding ? error(a, s, x.target) : 0.0, x.sp, v, x.holding, dt, rule,
                  reduced[i]);
          if (!x.holding) x.i = brake_limited(x.i, x.i_brake, x.i_hold);
          x.braking = !x.holding;
        }
        break;
      }
    }
    x.ff = 0;  // guide() sets it for one step
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

// X and Y held together: the NED position. A stick moved overrides both (a rate law on each,
// its setpoint ramped at max_accel); released, both brake (setpoints ramped to 0) and the
// position is held once both setpoints are 0 and both rates under capture_rate, or capture_s
// after the setpoints reached 0.
void RovAxes::step_xy(const RovState& s, const std::array<double, 6>& stick, double dt,
                      IntegratorRule rule, const std::array<bool, 6>& reduced,
                      std::array<double, 6>& out) {
  Axis& x = ax_[kX];
  Axis& y = ax_[kY];
  const RovGains& gx = g_[kX];
  const RovGains& gy = g_[kY];
  const double cy = std::cos(s.yaw), sy = std::sin(s.yaw);
  if (!x.sp_set || !y.sp_set) {
    x.sp = x.holding ? 0.0 : s.nu[kX];
    y.sp = y.holding ? 0.0 : s.nu[kY];
    x.sp_set = y.sp_set = true;
    i_ne_hold_ = i_ne_;  // entered: what it holds against so far
  }
  bool brake = false;
  if (stick[kX] != 0.0 || stick[kY] != 0.0) {
    x.holding = y.holding = false;
    x.since_release = 0;
    x.sp = slew(x.sp, stick[kX] * gx.max_rate, gx.max_accel, dt);
    y.sp = slew(y.sp, stick[kY] * gy.max_rate, gy.max_accel, dt);
  } else if (!x.holding) {
    brake = true;
    x.sp = slew(x.sp, 0, gx.max_accel, dt);
    y.sp = slew(y.sp, 0, gy.max_accel, dt);
    if (x.sp == 0.0 && y.sp == 0.0) {
      x.since_release += dt;
      const bool slow =
          std::fabs(s.nu[kX]) <= gx.capture_rate && std::fabs(s.nu[kY]) <= gy.capture_rate;
      if (slow || x.since_release >= gx.capture_s) {
        x.holding = y.holding = true;
        x.target = s.north;
        y.target = s.east;
      }
    }
  } else {
    x.sp = y.sp = 0;
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
  // guide()'s feed-forward is the target's NED rate: into the body frame, for this step.
  const double fu = x.holding ? cy * x.ff + sy * y.ff : 0.0;
  const double fv = x.holding ? -sy * x.ff + cy * y.ff : 0.0;
  x.ff = y.ff = 0;
  out[kX] = law(kX, ex, x.sp + fu, s.nu[kX], x.holding, dt, rule, reduced[kX]);
  out[kY] = law(kY, ey, y.sp + fv, s.nu[kY], x.holding, dt, rule, reduced[kY]);
  i_ne_ = {cy * x.i - sy * y.i, sy * x.i + cy * y.i};
  // The brake's integral limits, in NED (as the integral).
  if (brake && !x.braking) x.braking = true, i_ne_brake_ = i_ne_;
  if (brake && !x.holding) {
    i_ne_[0] = brake_limited(i_ne_[0], i_ne_brake_[0], i_ne_hold_[0]);
    i_ne_[1] = brake_limited(i_ne_[1], i_ne_brake_[1], i_ne_hold_[1]);
  }
  if (x.holding) i_ne_hold_ = i_ne_;
  if (!brake || x.holding) x.braking = false;
}

}  // namespace tiller::control
