#include "mission/sequencer.hpp"

#include <cmath>
#include <cstdio>

#include "mission/fence.hpp"

namespace tiller::mission {

namespace {
std::string where(const MissionPoint& p) {
  char b[64];
  std::snprintf(b, sizeof b, "(%.1f m north, %.1f m east)", p.north, p.east);
  return b;
}
}  // namespace

Sequencer::Sequencer(const Mission& m) : m_(m), jumps_left_(m.items.size(), 0) {
  for (std::size_t k = 0; k < m.items.size(); ++k)
    if (m.items[k].kind == ItemKind::kJump) jumps_left_[k] = m.items[k].repeat;
}

MissionPoint Sequencer::home_from(const MissionPoint& p) const {
  MissionPoint best = m_.home_point;
  double d = std::hypot(best.north - p.north, best.east - p.east);
  for (const auto& r : m_.rally) {
    const double dr = std::hypot(r.north - p.north, r.east - p.east);
    if (dr < d) {
      d = dr;
      best = r;
    }
  }
  best.has_heading = false;
  return best;
}

Sequencer::Action Sequencer::begin(const MissionPoint& vehicle, TimeUs now) {
  MissionPoint from = vehicle;
  from.has_heading = false;
  return build(from, now);
}

Sequencer::Action Sequencer::build(const MissionPoint& from, TimeUs now) {
  leg_.points.assign(1, from);
  leg_.points[0].has_heading = false;
  leg_.speeds.assign(1, speed_);
  after_ = State::kHolding;  // the items run out: hold the last point
  const auto push = [&](const MissionPoint& p) {
    const MissionPoint& last = leg_.points.back();
    if (std::hypot(p.north - last.north, p.east - last.east) < kSamePointM) {
      leg_.points.back() = p;  // the same point (its heading, if any): no zero-length segment
      return;
    }
    leg_.points.push_back(p);
    leg_.speeds.push_back(speed_);
  };
  const std::size_t n = m_.items.size();
  while (next_ < n) {
    if (leg_.points.size() >= kMaxLegPoints) {
      after_ = State::kFlying;  // a long jump loop: the next leg goes on from here
      break;
    }
    const Item& it = m_.items[next_];
    bool ends = false;
    switch (it.kind) {
      case ItemKind::kWaypoint:
        push(it.point);
        ++next_;
        break;
      case ItemKind::kSpeed:
        speed_ = it.speed;
        leg_.speeds.back() = speed_;
        ++next_;
        break;
      case ItemKind::kJump:
        if (jumps_left_[next_] != 0) {
          if (jumps_left_[next_] > 0) --jumps_left_[next_];
          next_ = static_cast<std::size_t>(it.jump_to);
        } else {
          ++next_;
        }
        break;
      case ItemKind::kLoiter:
        push(it.point);
        ++next_;
        if (it.loiter_s < 0) {
          next_ = n;  // for ever: the mission ends here
        } else {
          after_ = State::kLoitering;
          loiter_s_ = it.loiter_s;
        }
        ends = true;
        break;
      case ItemKind::kReturnHome:
        push(home_from(leg_.points.front()));
        next_ = n;
        after_ = m_.return_end == ReturnEnd::kHold ? State::kHolding : State::kStopped;
        ends = true;
        break;
      case ItemKind::kStop:
        if (it.has_point) push(it.point);
        next_ = n;
        after_ = State::kStopped;
        ends = true;
        break;
    }
    if (ends) break;
  }
  if (leg_.points.size() == 1) {  // nothing to fly: the end already
    state_ = after_ == State::kStopped ? State::kStopped : State::kHolding;
    status_ = state_ == State::kStopped ? "mission complete: stopped" : "mission complete: holding";
    return state_ == State::kStopped ? Action::kStop : Action::kNone;
  }
  ++legs_;
  state_ = State::kFlying;
  status_ = "leg " + std::to_string(legs_) + ": " + std::to_string(leg_.points.size() - 1) +
            " points to " + where(leg_.points.back());
  (void)now;
  return Action::kNewLeg;
}

Sequencer::Action Sequencer::on_leg_complete(TimeUs now) {
  if (state_ != State::kFlying) return Action::kNone;
  switch (after_) {
    case State::kFlying:
      return build(leg_.points.back(), now);
    case State::kLoitering:
      state_ = State::kLoitering;
      loiter_until_ = now + from_seconds(loiter_s_);
      status_ = "loitering " + std::to_string(static_cast<int>(std::lround(loiter_s_))) + " s at " +
                where(leg_.points.back());
      return Action::kNone;
    case State::kStopped:
      state_ = State::kStopped;
      status_ = "mission complete: stopped at " + where(leg_.points.back());
      return Action::kStop;
    default:
      state_ = State::kHolding;
      status_ = "mission complete: holding " + where(leg_.points.back());
      return Action::kNone;
  }
}

Sequencer::Action Sequencer::on_tick(TimeUs now) {
  if (state_ != State::kLoitering || now < loiter_until_) return Action::kNone;
  return build(leg_.points.back(), now);
}

Sequencer::Action Sequencer::on_position(double north, double east, TimeUs now) {
  if (m_.fence.empty() || breach_ >= 0 || state_ == State::kIdle || state_ == State::kStopped)
    return Action::kNone;
  const int b = fence_breach(m_.fence, north, east);
  if (b < 0) return Action::kNone;
  breach_ = b;
  MissionPoint here;
  here.north = north;
  here.east = east;
  status_ = "fence: " + std::string(m_.fence[b].inclusion ? "left " : "entered ") +
            describe_shape(m_.fence, b) + " at " + where(here) + ": ";
  switch (m_.fence_action) {
    case FenceAction::kHold:
      state_ = State::kFenceHold;
      status_ += "holding";
      return Action::kHold;
    case FenceAction::kNeutral:
      state_ = State::kStopped;
      status_ += "neutral (released)";
      return Action::kStop;
    case FenceAction::kReturn:
      break;
  }
  const std::string why = status_ + "returning home";
  next_ = m_.items.size();
  leg_.points.assign(1, here);
  leg_.speeds.assign(1, speed_);
  leg_.points.push_back(home_from(here));
  leg_.speeds.push_back(speed_);
  after_ = m_.return_end == ReturnEnd::kHold ? State::kHolding : State::kStopped;
  ++legs_;
  state_ = State::kFlying;
  status_ = why;
  (void)now;
  return Action::kNewLeg;
}

void leg_messages(const Leg& leg, std::int64_t path_id, path_t& path, path_speed_t& speed) {
  path.path_id = path_id;
  set_waypoints(path, leg.points);
  speed.path_id = path_id;
  speed.speed = leg.speeds;
  speed.n_segments = static_cast<std::int32_t>(speed.speed.size());
}

}  // namespace tiller::mission
