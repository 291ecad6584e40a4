#include "failsafe/failsafe_node.hpp"

#include <cmath>

#include <tiller/arm_request_t.hpp>

#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::failsafe {
namespace {
constexpr const char* kEventNames[6] = {"battery_warn", "battery_critical", "leak",
                                        "gnss_lost",    "geofence",         "depth_limit"};
}

FailsafeNode::FailsafeNode(const FailsafeNodeParams& p)
    : Node("failsafe", from_hz(p.rate_hz)), p_(p), monitor_(p.monitor) {
  subscribe(channels::kPower, &FailsafeNode::on_power);
  subscribe(channels::kLeak, &FailsafeNode::on_leak);
  subscribe(channels::kGnss, &FailsafeNode::on_gnss);
  subscribe(channels::kOdometry, &FailsafeNode::on_odometry);
  subscribe(channels::kMissionCommand, &FailsafeNode::on_mission_command);
  advertise<vehicle_status_t>(channels::kVehicleStatus);
  advertise<arm_request_t>(channels::kArmRequest);
  advertise<wrench_t>(channels::kWrenchFailsafe);
  wrench_.source = wrench_t::SOURCE_FAILSAFE;
  bad_power_ = &counter("rejected.power.invalid");
  bad_leak_ = &counter("rejected.leak.invalid");
  bad_gnss_ = &counter("rejected.gnss.invalid");
  bad_odometry_ = &counter("rejected.odometry.invalid");
  bad_command_ = &counter("rejected.mission_command.invalid");
  disarm_requests_ = &counter("disarm_requests");
  depth_invalid_ = &counter("odometry.depth_invalid");
  position_invalid_ = &counter("odometry.position_invalid");
  for (std::size_t i = 0; i < event_counters_.size(); ++i)
    event_counters_[i] = &counter(std::string("event.") + kEventNames[i]);
  status_.reason.reserve(128);
  health_text_.reserve(160);
  set_health(heartbeat_t::STATE_OK, std::string(160, ' '));
  set_health(heartbeat_t::STATE_OK, "starting");
}

void FailsafeNode::on_power(const power_t& m, TimeUs now) {
  if (!on_time(m.utime, now, p_.monitor.battery.stale, "power")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_power_);
    return;
  }
  power_at_ = now;
  // V + I R: the resting voltage when the pack's resistance is configured (sag compensated).
  monitor_.on_power(m.voltage + m.current * p_.monitor.battery.resistance_ohm, now);
}

void FailsafeNode::on_leak(const leak_t& m, TimeUs now) {
  if (!on_time(m.utime, now, p_.monitor.leak.stale, "leak")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_leak_);
    return;
  }
  leak_at_ = now;
  monitor_.on_leak(m.any_wet, now);
}

void FailsafeNode::on_gnss(const gnss_fix_t& m, TimeUs now) {
  if (!on_time(m.utime, now, p_.monitor.gnss.stale, "gnss")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_gnss_);
    return;
  }
  gnss_at_ = now;
  // Horizontal 1-sigma (m): the root sum of the north and east ones (0 = not reported).
  monitor_.on_gnss(m.fix_type, std::hypot(m.position_std[0], m.position_std[1]), now);
}

void FailsafeNode::on_odometry(const odometry_t& m, TimeUs now) {
  if (!on_time(m.utime, now, p_.monitor.odometry_stale, "odometry")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_odometry_);
    return;
  }
  odom_at_ = now;
  depth_ = m.position[2];
  depth_valid_ = (m.valid & odometry_t::VALID_DEPTH) != 0;
  const double c = std::cos(m.orientation[2]), s = std::sin(m.orientation[2]);
  const double u = m.velocity[0], v = m.velocity[1];
  // An invalid depth is no reading for the depth rule (it keeps its verdict): counted.
  if (!depth_valid_ && p_.monitor.depth.enabled) ++*depth_invalid_;
  // So is an invalid position for the geofence (GNSS lost is its own rule).
  const bool position_valid = (m.valid & odometry_t::VALID_POSITION) != 0;
  if (!position_valid && p_.monitor.geofence.enabled) ++*position_invalid_;
  monitor_.on_odometry(m.position[0], m.position[1], m.position[2], c * u - s * v, s * u + c * v,
                       position_valid, depth_valid_, now);
}

void FailsafeNode::on_mission_command(const mission_command_t& m, TimeUs now) {
  if (!on_time(m.utime, now, kEventMaxAgeUs, "mission_command")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_command_);
    return;
  }
  if (m.command != mission_command_t::START && m.command != mission_command_t::RESUME) return;
  for (const std::int64_t id : seen_ids_)
    if (id == m.command_id) return;  // a repeat
  seen_ids_[next_id_] = m.command_id;
  next_id_ = (next_id_ + 1) % seen_ids_.size();
  monitor_.on_operator_go(now);
}

void FailsafeNode::on_tick(TimeUs now) {
  const Status& s = monitor_.step(now);
  for (std::size_t i = 0; i < event_counters_.size(); ++i) {
    const std::int32_t bit = 1 << i;
    if ((s.latched & bit) != 0 && (counted_ & bit) == 0) ++*event_counters_[i];
  }
  counted_ = s.latched;
  status_.utime = now;
  status_.active = s.active;
  status_.latched = s.latched;
  status_.action = static_cast<std::int8_t>(s.action);
  if (s.changed) status_.reason = s.reason;
  publish(channels::kVehicleStatus, status_);
  wrench_.utime = now;
  wrench_.valid =
      s.action == Action::kSurface || s.action == Action::kRise || s.action == Action::kNeutral;
  const bool surfaced = odom_at_ >= 0 && now - odom_at_ <= p_.monitor.odometry_stale &&
                        depth_valid_ && depth_ < p_.surface_depth_m;
  wrench_.tau[2] = s.action == Action::kSurface ? (surfaced ? 0.0 : -p_.surface_thrust_n)
                   : s.action == Action::kRise  ? -p_.rise_thrust_n
                                                : 0.0;
  publish(channels::kWrenchFailsafe, wrench_);
  if (s.action == Action::kDisarm &&
      (disarm_sent_at_ < 0 || now - disarm_sent_at_ >= kUsPerSecond)) {
    disarm_sent_at_ = now;
    ++*disarm_requests_;
    arm_request_t r{};
    r.utime = now;
    r.arm = false;
    r.source = "failsafe";
    publish(channels::kArmRequest, r);
  }
  update_health(now);
}

void FailsafeNode::update_health(TimeUs now) {
  // A silent sensor of an enabled rule: DEGRADED (the rule cannot act without it).
  const MonitorParams& m = p_.monitor;
  const char* silent = nullptr;
  if (m.battery.enabled && (power_at_ < 0 || now - power_at_ > m.battery.stale))
    silent = "no power reading (TILLER_POWER): the battery rule is blind";
  else if (m.leak.enabled && (leak_at_ < 0 || now - leak_at_ > m.leak.stale))
    silent = "no leak reading (TILLER_LEAK): the leak rule is blind";
  else if ((m.geofence.enabled || m.depth.enabled) &&
           (odom_at_ < 0 || now - odom_at_ > m.odometry_stale))
    silent = "no odometry: the geofence and depth rules are blind";
  else if (m.geofence.enabled && !monitor_.position_known())
    silent = "odometry position invalid: the geofence is blind (keeps its last verdict)";
  else if (m.depth.enabled && !monitor_.depth_known())
    silent = "odometry depth invalid: the depth rule is blind (keeps its last verdict)";
  const Status& s = monitor_.status();
  std::int8_t state = heartbeat_t::STATE_OK;
  const char* text = "no failsafe event";
  if (s.reason[0] != '\0') {
    state = s.action == Action::kNone ? heartbeat_t::STATE_OK : heartbeat_t::STATE_DEGRADED;
    text = s.reason;
  } else if (silent != nullptr) {
    state = heartbeat_t::STATE_DEGRADED;
    text = silent;
  }
  if (state != health_ || health_text_ != text) {
    health_ = state;
    health_text_ = text;
    set_health(state, health_text_);
  }
}

}  // namespace tiller::failsafe
