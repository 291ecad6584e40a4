#include "guidance/path_follower.hpp"

#include <algorithm>
#include <cmath>

#include "guidance/pivot_turn.hpp"

namespace tiller::guidance {

PathFollower::PathFollower(const FollowerParams& p) : p_(p) {}

void PathFollower::clear() {
  pts_.clear();
  tail_length_.clear();
  min_dist_.clear();
  seg_ = 0;
  complete_ = false;
  skipped_ = 0;
  stepped_back_ = 0;
  entered_by_cut_ = false;
  entered_by_skip_ = false;
  state_ = 0;
  world_integral_.setZero();
  crab_world_.setZero();
  on_arc_ = false;
  last_pos_valid_ = false;
  along_seg_ = -1;
  along_current_ = 0;
  reset_pivot();
}

void PathFollower::reset_pivot() {
  pivot_seg_ = -1;
  pivot_active_ = false;
  pivot_done_ = false;
  pivot_time_ = 0;
}

bool PathFollower::pivot_corner(int seg) const {
  const int n = static_cast<int>(pts_.size());
  if (!p_.turn_pivot || seg < 0 || seg + 2 >= n) return false;
  const auto k = static_cast<std::size_t>(seg);
  const Vec2 t1 = (pts_[k + 1].position - pts_[k].position).normalized();
  const Vec2 t2 = (pts_[k + 2].position - pts_[k + 1].position).normalized();
  return std::acos(std::clamp(t1.dot(t2), -1.0, 1.0)) >= p_.pivot_min_angle;
}

void PathFollower::arc_for(double angle, double& radius, double& speed) const {
  radius = 0;
  speed = 0;
  if (!p_.turn_arc || !(p_.turn_rate > 0) || angle < 1e-3 || angle > 2 * kPi / 3) return;
  speed = p_.max_speed * turn_factor(angle);
  radius = speed / p_.turn_rate;
  const double inside = 1 / std::cos(angle / 2) - 1;  // per metre of radius
  if (radius * inside > p_.turn_arc_inside_max) {
    radius = p_.turn_arc_inside_max / inside;
    speed = radius * p_.turn_rate;
  }
}

bool PathFollower::set_path(const std::vector<Waypoint>& points, const Vec2& vehicle,
                            double heading, bool is_translation) {
  clear();
  is_translation_ = is_translation;
  for (const auto& w : points) {
    if (!w.position.allFinite()) continue;
    if (!pts_.empty() && (w.position - pts_.back().position).norm() < p_.min_segment_length) {
      // A repeated point (zero-length segment): keep one, with the later heading if given.
      if (w.has_heading) {
        pts_.back().has_heading = true;
        pts_.back().heading = wrap_pi(w.heading);
      }
      continue;
    }
    Waypoint c = w;
    c.heading = wrap_pi(c.heading);
    pts_.push_back(c);
  }
  if (pts_.empty()) return false;
  if (pts_.size() == 1 && vehicle.allFinite() &&
      (pts_[0].position - vehicle).norm() >= p_.min_segment_length) {
    Waypoint start;
    start.position = vehicle;
    pts_.insert(pts_.begin(), start);
  }
  const auto n = pts_.size();
  tail_length_.assign(n, 0.0);
  for (std::size_t k = n - 1; k-- > 0;) {
    tail_length_[k] = tail_length_[k + 1] + (pts_[k + 1].position - pts_[k].position).norm();
  }
  min_dist_.assign(n, 1e300);
  goal_heading_valid_ = pts_.back().has_heading;
  goal_heading_ = pts_.back().heading;
  if (!goal_heading_valid_ && is_translation && std::isfinite(heading)) {
    goal_heading_valid_ = true;
    goal_heading_ = wrap_pi(heading);
  }
  if (std::isfinite(heading)) {
    last_heading_ = wrap_pi(heading);
    last_heading_valid_ = true;
  }
  if (n == 1) complete_ = true;  // already there
  return true;
}

void PathFollower::set_translation(bool is_translation, double heading) {
  if (is_translation == is_translation_) return;
  is_translation_ = is_translation;
  if (pts_.empty() || pts_.back().has_heading) return;
  goal_heading_valid_ = is_translation && std::isfinite(heading);
  goal_heading_ = goal_heading_valid_ ? wrap_pi(heading) : 0.0;
}

double PathFollower::end_speed(double remaining) const {
  remaining = std::max(0.0, remaining);
  if (p_.end_slowdown == EndSlowdown::kLinear) {
    if (remaining >= p_.end_slowdown_distance) return p_.max_speed;
    return std::min(p_.max_speed, remaining / p_.end_divisor_s);
  }
  return std::min(p_.max_speed, std::sqrt(2.0 * p_.braking_decel * remaining));
}

double PathFollower::turn_factor(double angle) const {
  return std::clamp(1.0 - p_.turn_reduction * std::abs(angle) / kPi, p_.turn_min_fraction, 1.0);
}

double PathFollower::los_heading(double path, double e) const {
  const double d = p_.lookahead;
  switch (p_.law) {
    case CrossTrackLaw::kLos:
      return wrap_pi(path - std::atan(e / d));
    case CrossTrackLaw::kIntegral:
      return wrap_pi(path - std::atan((e + p_.integral_kappa * state_) / d));
    case CrossTrackLaw::kAdaptive:
      return wrap_pi(path - state_ - std::atan(e / d));
    case CrossTrackLaw::kSeed:
    case CrossTrackLaw::kWorldIntegral:
      break;
  }
  return wrap_pi(path);
}

double PathFollower::wheel_over(double angle, double speed) const {
  if (!(p_.turn_rate > 0)) return 0;
  const double r = std::max(0.0, speed) / p_.turn_rate;
  return r * std::tan(std::min(std::abs(angle), 2 * kPi / 3) / 2);
}

Vec2 PathFollower::current_estimate() const {
  if (p_.law == CrossTrackLaw::kWorldIntegral) return -world_integral_;
  if (p_.law == CrossTrackLaw::kIntegral || p_.law == CrossTrackLaw::kAdaptive)
    return -crab_world_ * p_.max_speed;
  return Vec2(0, 0);
}

void PathFollower::observe_current_along(double heading, double current) {
  if (!std::isfinite(heading) || !std::isfinite(current) || !last_pos_valid_ || complete_) return;
  const int n = static_cast<int>(pts_.size());
  if (seg_ + 1 >= n) return;
  const Vec2& p1 = pts_[static_cast<std::size_t>(seg_)].position;
  const Vec2& p2 = pts_[static_cast<std::size_t>(seg_ + 1)].position;
  const double len = (p2 - p1).norm();
  const Vec2 t = (p2 - p1) / len;
  const double along = t.dot(last_pos_ - p1);
  const bool last = seg_ + 2 >= n;
  // Not within the turn's slow-down (nor kAlongSettleDistance before it): braking for the turn
  // leaves the integral off its steady value.
  const double end_zone = last ? 0.0 : p_.turn_slowdown_distance + kAlongSettleDistance;
  if (along < kAlongSettleDistance || along > len - end_zone) return;
  const Vec2 h(std::cos(heading), std::sin(heading));
  const double th = t.dot(h);
  if (th < std::cos(kPi / 6)) return;
  // current . h = c_t (t . h) + c_n (n . h), c_n the law's estimate across the leg.
  const Vec2 nrm(-t.y(), t.x());
  const double c_n = nrm.dot(current_estimate());
  along_current_ = (current - c_n * nrm.dot(h)) / th;
  along_seg_ = seg_;
}

Vec2 PathFollower::current_full() const {
  const Vec2 est = current_estimate();
  const int n = static_cast<int>(pts_.size());
  if (along_seg_ != seg_ || complete_ || seg_ + 1 >= n) return est;
  const Vec2 t = Vec2(pts_[static_cast<std::size_t>(seg_ + 1)].position -
                      pts_[static_cast<std::size_t>(seg_)].position)
                     .normalized();
  return est + t * (along_current_ - t.dot(est));
}

double PathFollower::drift_lead(const Vec2& t1, const Vec2& t2, double angle) const {
  // Not for a hairpin (above 120 deg, where the wheel-over is capped too): its outside is along
  // the new leg, and a turn started earlier only passes farther from the point.
  if (!(p_.turn_drift_rate > 0) || angle < 1e-3 || angle > 2 * kPi / 3) return 0;
  // The outside of the turn, across the new leg: t1's part normal to t2 (length sin(angle)).
  const Vec2 out = t1 - t2 * t1.dot(t2);
  const double s = out.norm();
  const double drift = current_full().dot(out / s) * angle / p_.turn_drift_rate;
  const double wo = wheel_over(angle, p_.max_speed * turn_factor(angle));
  return std::clamp(drift / s, -wo, wo);
}

double PathFollower::crab() const {
  if (p_.law == CrossTrackLaw::kIntegral) {
    return std::atan(p_.integral_kappa * state_ / p_.lookahead);
  }
  return p_.law == CrossTrackLaw::kAdaptive ? state_ : 0.0;
}

// The state is the crab angle that cancels the current's component along the path normal: a
// world-frame current estimate of which each leg observes only the part along its normal. Kept
// as a world vector (crab_world_: sin(beta) along the left normal, i.e. the current over the
// speed; world_integral_: the correction itself), each leg refreshes its normal component and
// leaves the rest: what the earlier legs learnt of the current along this leg's direction. At a
// switch the new leg's state is the stored vector's component along its normal, so after two
// legs of different directions the whole current is known and a corner no longer starts with
// the new leg's cross current unknown (issue 13: the boat drifted wide until the integral caught
// up). The part of the vector along a leg is never applied there (it would only add to or take
// from the along-path speed: issue 13 finding 2).
void PathFollower::carry_state(int from_seg, int to_seg) {
  const int n = static_cast<int>(pts_.size());
  const bool valid = from_seg >= 0 && to_seg >= 0 && from_seg + 1 < n && to_seg + 1 < n;
  const auto dir = [&](int k) {
    return Vec2(pts_[static_cast<std::size_t>(k + 1)].position -
                pts_[static_cast<std::size_t>(k)].position)
        .normalized();
  };
  // A measured current along the leg just left (observe_current_along) replaces what the law
  // holds along it: at a corner the new leg starts with the whole current known.
  const bool measured = valid && along_seg_ == from_seg && to_seg == from_seg + 1;
  if (p_.law == CrossTrackLaw::kWorldIntegral) {
    if (!valid) world_integral_.setZero();
    if (measured) {
      const Vec2 t1 = dir(from_seg);
      world_integral_ += t1 * (-along_current_ - t1.dot(world_integral_));
      const double m = world_integral_.norm();
      if (m > p_.integral_limit) world_integral_ *= p_.integral_limit / m;
    }
    return;  // applied as its component along the segment's normal (update)
  }
  if (p_.law != CrossTrackLaw::kIntegral && p_.law != CrossTrackLaw::kAdaptive) return;
  if (!valid) {
    state_ = 0;
    crab_world_.setZero();
    return;
  }
  const Vec2 t1 = dir(from_seg), t2 = dir(to_seg);
  const Vec2 n1(t1.y(), -t1.x()), n2(t2.y(), -t2.x());  // left normals (NED)
  // The leg just left: its normal component is the state (set_state may have changed it).
  crab_world_ += n1 * (std::sin(crab()) - n1.dot(crab_world_));
  if (measured) crab_world_ += t1 * (-along_current_ / p_.max_speed - t1.dot(crab_world_));
  const double lim = std::sin(p_.max_crab);
  if (crab_world_.norm() > 1) crab_world_.normalize();
  const double beta = std::asin(std::clamp(n2.dot(crab_world_), -lim, lim));
  state_ =
      p_.law == CrossTrackLaw::kIntegral ? p_.lookahead * std::tan(beta) / p_.integral_kappa : beta;
}

FollowerOutput PathFollower::update(const Vec2& pos, double heading, double dt) {
  FollowerOutput out;
  if (pts_.empty() || !pos.allFinite() || !std::isfinite(heading)) return out;
  out.active = true;
  last_pos_ = pos;
  last_pos_valid_ = true;
  const int n = static_cast<int>(pts_.size());
  for (int k = seg_; k < n; ++k) {
    min_dist_[static_cast<std::size_t>(k)] =
        std::min(min_dist_[static_cast<std::size_t>(k)],
                 (pts_[static_cast<std::size_t>(k)].position - pos).norm());
  }

  // Segment selection: the seed's behind / middle / in-front test, skipping passed points.
  SegmentRelation rel = SegmentRelation::kMiddle;
  while (!complete_) {
    if (seg_ + 1 >= n) {
      complete_ = true;
      break;
    }
    const Vec2& p1 = pts_[static_cast<std::size_t>(seg_)].position;
    const Vec2& p2 = pts_[static_cast<std::size_t>(seg_ + 1)].position;
    const Vec2 s = p2 - p1;
    const double a = s.dot(pos - p1);
    const double b = s.dot(pos - p2);
    rel = a < 0 ? SegmentRelation::kBehind
                : (b > 0 ? SegmentRelation::kInFront : SegmentRelation::kMiddle);
    const double d2 = (pos - p2).norm();
    const bool last = seg_ + 1 == n - 1;
    const bool reached = d2 < p_.acceptance_radius;
    bool cut = !last && d2 < p_.corner_cut_radius;
    bool arc_cut = false;  // left at the arc's start: the corner is flown along it
    bool defer = false;    // a water turn starts later: reaching p2 does not end the segment
    bool water_cut = false;
    const bool pivot_here = pivot_corner(seg_);
    if (pivot_here) {
      // Flown as a pivot: the segment ends when the turn in place has ended (update's leg part).
      cut = false;
      defer = !(pivot_done_ && pivot_seg_ == seg_);
    } else if (!last && p_.turn_rate > 0 && rel == SegmentRelation::kMiddle) {
      // Turn anticipation: leave the segment at the wheel-over point.
      const Vec2 t1 = s.normalized();
      const Vec2 t2 = (pts_[static_cast<std::size_t>(seg_ + 2)].position - p2).normalized();
      const double angle = std::acos(std::clamp(t1.dot(t2), -1.0, 1.0));
      double radius = 0, speed = 0;
      arc_for(angle, radius, speed);
      WaterTurn wt;
      if (radius > 0 && p_.turn_arc_water)
        wt = plan_water_turn(t1, t2, current_full(), speed, p_.turn_rate);
      const double wo0 = wt.valid     ? wt.lead
                         : radius > 0 ? radius * std::tan(angle / 2)
                                      : wheel_over(angle, p_.max_speed * turn_factor(angle));
      const double wo = wo0 + (radius > 0 ? 0.0 : drift_lead(t1, t2, angle));
      const double ahead = t1.dot(p2 - pos);  // along-track distance to p2
      defer = wt.valid && ahead >= wo;
      if (ahead < wo && d2 < 2 * std::max(wo, wo0) + p_.corner_cut_radius) {
        cut = true;
        if (wt.valid) {
          wturn_ = wt;
          wturn_origin_ = pos;
          wturn_tau_ = 0;
          arc_speed_ = speed;
          arc_cut = true;
          water_cut = true;
        } else if (radius > 0) {
          wturn_.valid = false;
          arc_ = make_turn_arc(p2, t1, t2, radius);
          arc_speed_ = speed;
          arc_cut = arc_.valid;
        }
      }
    }
    if (defer) cut = false;  // not the corner cut either: the turn starts at its point
    const bool ends =
        pivot_here ? !defer : (reached && !defer) || cut || rel == SegmentRelation::kInFront;
    if (ends) {
      const bool skip =
          min_dist_[static_cast<std::size_t>(seg_ + 1)] >= p_.acceptance_radius && !cut;
      if (skip) ++skipped_;
      carry_state(seg_, seg_ + 1);
      ++seg_;
      on_arc_ = arc_cut && (water_cut || !reached);
      entered_by_cut_ = cut || pivot_here;
      reset_pivot();
      entered_by_skip_ = skip;
      if (last) complete_ = true;
      continue;
    }
    // Behind the segment (the seed: "most likely the vehicle should decrement the selected
    // point, as it is likely on the previous line segment"), other than after a corner cut:
    // step back, but only when the vehicle is really on the previous segment (in its middle)
    // and not within acceptance_radius of the point between them (which it would reach again
    // at once: no back-and-forth). A point counted as skipped is uncounted: it can still be
    // reached.
    if (rel == SegmentRelation::kBehind && seg_ > 0 && !entered_by_cut_ &&
        (pos - p1).norm() >= std::max(p_.acceptance_radius, p_.corner_cut_radius)) {
      const Vec2& p0 = pts_[static_cast<std::size_t>(seg_ - 1)].position;
      const Vec2 s0 = p1 - p0;
      if (s0.dot(pos - p0) >= 0 && s0.dot(pos - p1) <= 0) {
        if (entered_by_skip_) --skipped_;
        carry_state(seg_, seg_ - 1);
        --seg_;
        on_arc_ = false;
        reset_pivot();
        entered_by_cut_ = false;
        entered_by_skip_ = false;
        ++stepped_back_;
        continue;
      }
    }
    break;
  }

  const Vec2 goal = pts_.back().position;
  out.distance_to_goal = (goal - pos).norm();
  out.skipped = skipped_;
  out.stepped_back = stepped_back_;
  out.relation = rel;
  Vec2 v(0, 0);
  if (complete_) {
    // Path done: head for the goal with the end slow-down (station keeping takes over near it).
    out.segment = n - 1;
    out.complete = true;
    out.remaining_path = out.distance_to_goal;
    if (out.distance_to_goal > 1e-9) {
      v = (goal - pos) / out.distance_to_goal * end_speed(out.distance_to_goal);
    }
    out.along_speed = v.norm();
  }
  ArcPosition ap;
  const bool water_turn = on_arc_ && wturn_.valid;
  Vec2 ref(0, 0);  // the water turn's ground track now
  if (!complete_ && water_turn) {
    wturn_tau_ += std::max(0.0, dt);
    ref = wturn_origin_ + ground_offset(wturn_, wturn_tau_);
    if (wturn_tau_ >= wturn_.duration || (ref - pos).norm() > p_.parallel_cutoff_distance)
      on_arc_ = false;
  } else if (!complete_ && on_arc_) {
    ap = locate(arc_, pos);
    if (ap.past_end || std::abs(ap.outside) > p_.parallel_cutoff_distance) on_arc_ = false;
  }
  double course_rate = 0;      // rad/s: the course's turn rate on an arc (+ clockwise)
  Vec2 heading_current(0, 0);  // the heading points along v - this (the water turn's current)
  if (!complete_ && on_arc_ && water_turn) {
    // The corner through the water: the planned velocity through the water plus the current,
    // and the way back to the planned track as the approach to a leg (path_follower.hpp).
    const Vec2& p1 = pts_[static_cast<std::size_t>(seg_)].position;
    const Vec2& p2 = pts_[static_cast<std::size_t>(seg_ + 1)].position;
    const Vec2 t = (p2 - p1).normalized();
    out.segment = seg_;
    out.on_arc = true;
    out.cross_track = -(pos - p1).x() * t.y() + (pos - p1).y() * t.x();
    out.along_track_remaining = (p2 - p1).norm() - t.dot(pos - p1);
    out.remaining_path =
        std::max(0.0, out.along_track_remaining) + tail_length_[static_cast<std::size_t>(seg_ + 1)];
    const Vec2 w = water_velocity(wturn_, wturn_tau_);
    const Vec2 to_ref = ref - pos;
    const double e = to_ref.norm();
    out.approach_speed = std::min(p_.approach_max_speed, e / p_.approach_divisor_s);
    v = w + wturn_.current + (e > 1e-9 ? Vec2(to_ref / e * out.approach_speed) : Vec2(0, 0));
    const double m = v.norm();
    if (m > p_.max_speed) v *= p_.max_speed / m;
    out.along_speed = arc_speed_;
    out.turn_factor = arc_speed_ / p_.max_speed;
    course_rate = (wturn_.dpsi > 0 ? 1.0 : -1.0) * p_.turn_rate;
    heading_current = wturn_.current;
    out.crab = crab();
  } else if (!complete_ && on_arc_) {
    // The corner along its arc: U along it, the approach to it and the current correction's
    // radial part along the radius (path_follower.hpp).
    const Vec2& p1 = pts_[static_cast<std::size_t>(seg_)].position;
    const Vec2& p2 = pts_[static_cast<std::size_t>(seg_ + 1)].position;
    const Vec2 t = (p2 - p1).normalized();
    out.segment = seg_;
    out.on_arc = true;
    out.cross_track = -arc_.sign * ap.outside;  // outside a right turn is left of the track
    out.along_track_remaining = (p2 - p1).norm() - t.dot(pos - p1);
    out.remaining_path =
        std::max(0.0, out.along_track_remaining) + tail_length_[static_cast<std::size_t>(seg_ + 1)];
    const double u = std::min(arc_speed_, end_speed(out.remaining_path));
    out.along_speed = u;
    out.turn_factor = u / p_.max_speed;
    const double e = ap.outside;
    out.approach_speed = std::min(p_.approach_max_speed, std::abs(e) / p_.approach_divisor_s);
    const double radial =
        (e > 0 ? 1.0 : -1.0) * out.approach_speed - ap.inward.dot(current_estimate());
    v = ap.tangent * u + ap.inward * radial;
    const double m = v.norm();
    if (m > p_.max_speed) v *= p_.max_speed / m;
    course_rate = arc_.sign * u / arc_.radius;
    out.crab = crab();
  } else if (!complete_) {
    const Vec2& p1 = pts_[static_cast<std::size_t>(seg_)].position;
    const Vec2& p2 = pts_[static_cast<std::size_t>(seg_ + 1)].position;
    const double len = (p2 - p1).norm();
    const Vec2 t = (p2 - p1) / len;
    const double along = t.dot(pos - p1);
    const Vec2 foot = p1 + t * along;
    const Vec2 to_path = foot - pos;
    const double e = to_path.norm();
    out.segment = seg_;
    out.cross_track = -(pos - p1).x() * t.y() + (pos - p1).y() * t.x();
    out.along_track_remaining = len - along;
    out.remaining_path =
        std::max(0.0, len - along) + tail_length_[static_cast<std::size_t>(seg_ + 1)];

    const bool seed_law = p_.law == CrossTrackLaw::kSeed || p_.law == CrossTrackLaw::kWorldIntegral;
    // Along the path.
    double along_speed = seed_law
                             ? p_.max_speed * std::max(0.0, 1.0 - e / p_.parallel_cutoff_distance)
                             : p_.max_speed;
    if (seg_ + 2 < n) {
      const Vec2 t2 = (pts_[static_cast<std::size_t>(seg_ + 2)].position - p2).normalized();
      const double angle = std::acos(std::clamp(t.dot(t2), -1.0, 1.0));
      double radius = 0, arc_speed = 0;
      const bool pivot = pivot_corner(seg_);
      if (!pivot) arc_for(angle, radius, arc_speed);
      WaterTurn wt;
      if (radius > 0 && p_.turn_arc_water)
        wt = plan_water_turn(t, t2, current_full(), arc_speed, p_.turn_rate);
      if (pivot) {
        // A pivot: brake to S (set back by the drift the current estimate predicts; fixed once
        // the pivot has started) and start turning in place there.
        if (!pivot_active_) {
          const Vec2 c = current_full();
          pivot_point_ = p2 - t * pivot_setback(t, t2, c, p_.pivot_turn_rate, p_.pivot_allowance,
                                                p_.pivot_max_offset);
          const Vec2 n2(-t2.y(), t2.x());
          const Vec2 h2 = t2 * p_.max_speed - n2 * n2.dot(c);  // the next leg's crab
          pivot_heading_ = std::atan2(h2.y(), h2.x());
        }
        const double to_s = t.dot(pivot_point_ - pos);
        out.wheel_over = t.dot(p2 - pivot_point_);
        if (!pivot_active_ && to_s <= p_.pivot_trigger) {
          pivot_active_ = true;
          pivot_seg_ = seg_;
          pivot_time_ = 0;
        }
        out.turn_factor = std::sqrt(2.0 * p_.braking_decel * std::max(0.0, to_s)) / p_.max_speed;
        along_speed = std::min(along_speed, p_.max_speed * out.turn_factor);
      } else
        out.wheel_over = wt.valid     ? wt.lead
                         : radius > 0 ? radius * std::tan(angle / 2)
                                      : wheel_over(angle, p_.max_speed * turn_factor(angle)) +
                                            drift_lead(t, t2, angle);
      if (wt.valid && (p2 - pos).norm() < p_.turn_slowdown_distance + out.wheel_over) {
        // At the water turn's ground speed before it starts (its speed through the water).
        out.turn_factor = wt.ground1 / p_.max_speed;
        along_speed = std::min(along_speed, wt.ground1);
      } else if (radius > 0 && (p2 - pos).norm() < p_.turn_slowdown_distance + out.wheel_over) {
        out.turn_factor = arc_speed / p_.max_speed;  // at the arc's speed before it starts
        along_speed = std::min(along_speed, arc_speed);
      } else if (radius == 0 && (p2 - pos).norm() < p_.turn_slowdown_distance) {
        out.turn_factor = turn_factor(angle);
        along_speed = std::min(along_speed, p_.max_speed * out.turn_factor);
      }
    }
    if (p_.turn_rate > 0 && seg_ > 0 && (p1 - pos).norm() < p_.turn_slowdown_distance) {
      // With turn anticipation the turn is flown after the switch: keep its speed through it.
      const Vec2 t0 = (p1 - pts_[static_cast<std::size_t>(seg_ - 1)].position).normalized();
      const double f = turn_factor(std::acos(std::clamp(t0.dot(t), -1.0, 1.0)));
      out.turn_factor = std::min(out.turn_factor, f);
      along_speed = std::min(along_speed, p_.max_speed * f);
    }
    along_speed = std::min(along_speed, end_speed(out.remaining_path));
    out.along_speed = along_speed;
    if (seed_law) {
      // Toward the path.
      out.approach_speed = std::min(p_.approach_max_speed, e / p_.approach_divisor_s);
      Vec2 v_perp = e > 1e-9 ? Vec2(to_path / e * out.approach_speed) : Vec2(0, 0);
      if (p_.law == CrossTrackLaw::kWorldIntegral) {
        // As for the LOS laws, not while a turn is flown (its error is the turn's).
        const bool in_turn =
            p_.turn_rate > 0 && seg_ > 0 && (p1 - pos).norm() < p_.turn_slowdown_distance;
        if (dt > 0 && e < p_.integral_zone && !in_turn) {
          world_integral_ += p_.integral_gain * to_path * dt;
          const double m = world_integral_.norm();
          if (m > p_.integral_limit) world_integral_ *= p_.integral_limit / m;
        }
        // Only its component along the normal (to_path is along it): the rest is what earlier
        // legs learnt of the current along this leg (carry_state).
        const Vec2 normal(-t.y(), t.x());
        v_perp += normal * normal.dot(world_integral_);
      }
      v = t * along_speed + v_perp;
      // The heading along the velocity through the water: the law's correction stands for the
      // current across the leg; the current along it (current_full) matters at a turn's low speed.
      if (p_.turn_arc_water) heading_current = t * t.dot(current_full());
      // Never above max_speed (the correction added to a full along-path speed went up to
      // 1.85 m/s for 1.5: issue 13 finding 2): scale, keeping the direction.
      const double m = v.norm();
      if (m > p_.max_speed) v *= p_.max_speed / m;
    } else {
      const double ye = out.cross_track;
      const double d = p_.lookahead;
      // No integration while a turn is flown (within turn_slowdown_distance after the corner):
      // the cross-track error there is the turn's, not the current's (it wound the state up and
      // doubled the overshoot).
      const bool in_turn = seg_ > 0 && (p1 - pos).norm() < p_.turn_slowdown_distance;
      if (dt > 0 && std::abs(ye) < p_.integral_zone && !in_turn) {
        if (p_.law == CrossTrackLaw::kIntegral) {
          const double s_ = ye + p_.integral_kappa * state_;
          state_ += dt * d * ye / (s_ * s_ + d * d);
          const double lim = d * std::tan(p_.max_crab) / p_.integral_kappa;
          state_ = std::clamp(state_, -lim, lim);
        } else if (p_.law == CrossTrackLaw::kAdaptive) {
          state_ += dt * p_.adaptive_gamma * d * ye / std::sqrt(d * d + ye * ye);
          state_ = std::clamp(state_, -p_.max_crab, p_.max_crab);
        }
      }
      const Vec2 nl(t.y(), -t.x());  // left normal: the state's part of the world estimate
      crab_world_ += nl * (std::sin(crab()) - nl.dot(crab_world_));
      const double chi = los_heading(std::atan2(t.y(), t.x()), ye);
      v = Vec2(std::cos(chi), std::sin(chi)) * along_speed;
    }
    out.crab = crab();
  }

  // Heading: along the desired velocity, or the goal heading near the goal / when translating.
  // "Near the goal" only on the last segment (or once complete), with both the path left and
  // the straight line to the goal below goal_heading_distance: on a closed course the goal is
  // also the start, and there the boat must head along the first segment, not face the goal's
  // heading (which turned the Otter -0.7 rad and 2 m off the first leg).
  if (pivot_active_ && !complete_) {
    // Turning in place: hold S (surge cancels the current along the heading).
    pivot_time_ += std::max(0.0, dt);
    v = (pivot_point_ - pos) * p_.pivot_hold_gain;
    const double m = v.norm();
    if (m > p_.approach_max_speed) v *= p_.approach_max_speed / m;
    out.pivot = true;
  }
  const double speed = v.norm();
  const bool last_leg = complete_ || seg_ + 2 >= n;
  const bool near_goal = last_leg && out.remaining_path < p_.goal_heading_distance &&
                         out.distance_to_goal < p_.goal_heading_distance;
  bool along_velocity = false;
  if (out.pivot) {
    last_heading_ = pivot_heading_;
    last_heading_valid_ = true;
    if (std::abs(angle_diff(pivot_heading_, heading)) < p_.pivot_exit_angle ||
        pivot_time_ > p_.pivot_timeout_s)
      pivot_done_ = true;  // the segment ends at the next update
  } else if (is_translation_ || (near_goal && goal_heading_valid_)) {
    if (goal_heading_valid_) {
      last_heading_ = goal_heading_;
      last_heading_valid_ = true;
    }
  } else if (speed > 1e-3) {
    const Vec2 hv = v - heading_current;
    last_heading_ = std::atan2(hv.y(), hv.x());
    // (wrap_pi only with a lead: off an arc the heading stays bit for bit what it was.)
    if (course_rate != 0) last_heading_ = wrap_pi(last_heading_ + course_rate * p_.heading_lead_s);
    last_heading_valid_ = true;
    along_velocity = true;
  }
  out.target_heading = last_heading_;
  out.heading_valid = last_heading_valid_;
  if (along_velocity) {
    // Against the course (the lead on an arc is the heading loop's, not an error to slow for).
    // Not on a water turn: it is planned at the hull's own turn rate, its speed held.
    const Vec2 hv = v - heading_current;
    const double err = std::abs(angle_diff(std::atan2(hv.y(), hv.x()), heading));
    if (!(water_turn && out.on_arc))
      out.heading_factor = std::max(0.0, 1.0 - err / p_.heading_slowdown_angle);
    v *= out.heading_factor;
  }
  out.velocity = v;
  return out;
}

}  // namespace tiller::guidance
