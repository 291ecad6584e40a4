#include "launch/monitor.hpp"

#include <algorithm>
#include <string>

#include "core/message_checks.hpp"
#include "runtime/heartbeat_name.hpp"

namespace tiller::launch {

LaunchMonitor::LaunchMonitor(Supervisor& sup) : Node("launch", kTickUs), sup_(sup) {
  std::vector<std::string> subscribed;
  std::size_t named = 0;
  for (const auto& p : sup_.processes()) {
    // Two counters a process, for the first kNamedProcesses (a heartbeat holds 64 counters).
    const bool own = named++ < kNamedProcesses;
    silent_.push_back(own ? &counter("watchdog.silent." + p.spec.name) : &spare_);
    restarts_.push_back(own ? &counter("restarts." + p.spec.name) : &spare_);
    if (p.spec.liveness_s <= 0) continue;
    ++watched_;
    const std::string& node = p.spec.heartbeat_node();
    const std::string ch = heartbeat_channel_of(node);
    if (std::find(subscribed.begin(), subscribed.end(), ch) != subscribed.end()) continue;
    subscribed.push_back(ch);
    subscribe(ch, &LaunchMonitor::on_heartbeat);
    accept_only_from(ch, {node});
  }
  // Its own heartbeat coming back says the bus works (Supervisor::on_bus).
  subscribe(heartbeat_channel(), &LaunchMonitor::on_heartbeat);
  accept_only_from(heartbeat_channel(), {name()});
  invalid_ = &counter("rejected.heartbeat.invalid");
  unknown_ = &counter("rejected.heartbeat.unknown");
  refresh();
}

void LaunchMonitor::on_heartbeat(const heartbeat_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(*invalid_);
    return;
  }
  if (m.process == name()) {
    sup_.on_bus(now);
    return;
  }
  if (!sup_.on_heartbeat(m.process, now)) reject(*unknown_);
}

void LaunchMonitor::refresh() {
  bool degraded = false;
  const auto& procs = sup_.processes();
  for (std::size_t i = 0; i < procs.size(); ++i) {
    const auto& p = procs[i];
    *silent_[i] = p.silent_stops;
    *restarts_[i] = p.restarts;
    degraded = degraded || p.state == State::kSilent || p.state == State::kBackoff ||
               p.state == State::kGaveUp;
  }
  set_health(degraded ? heartbeat_t::STATE_DEGRADED : heartbeat_t::STATE_OK,
             sup_.last_silent().empty() ? std::to_string(watched_) + " processes watched (liveness)"
                                        : sup_.last_silent());
}

void LaunchMonitor::on_tick(TimeUs now) {
  (void)now;
  refresh();
}

void LaunchMonitor::after_poll(TimeUs now) {
  if (sup_.silent_stops() == silent_seen_) return;
  silent_seen_ = sup_.silent_stops();
  refresh();
  publish_heartbeat_now(now);
}

}  // namespace tiller::launch
