// CockpitNode's pilot commands: the page's gamepad as a pilot source (TILLER_MANUAL_DEMAND, under
// tiller-teleop's rules: one pilot page, centred first, neutral and invalid at once on any loss)
// and the thruster test's hold-to-spin requests (TILLER_THRUSTER_TEST, through
// cockpit/thruster_test.hpp; the mixer's intent gate decides). The rules: cockpit/cockpit_node.hpp.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "cockpit/cockpit_node_parts.hpp"
#include "runtime/channels.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller::cockpit {

using nlohmann::json;

void CockpitNode::publish_demand(TimeUs now, bool valid) {
  demand_msg_.utime = now;
  for (int i = 0; i < 6; ++i)
    demand_msg_.demand[i] = valid ? demand_[static_cast<std::size_t>(i)] : 0.0;
  demand_msg_.valid = valid;
  if (demand_msg_.station != p_.station) demand_msg_.station = p_.station;
  publish(channels::kManualDemand, demand_msg_);
}

void CockpitNode::pilot_lost(TimeUs now, std::int64_t& why) {
  ++why;
  demand_.fill(0.0);
  centred_ = false;
  pilot_ = -1;
  publish_demand(now, false);
}

void CockpitNode::on_gamepad(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  if (pilot_ >= 0 && pilot_ != client) {
    refuse(client, "gamepad", *other_pilot_, "another page is the pilot");
    return;
  }
  const json* conn = member(j, "connected");
  if (conn && !(conn->is_boolean() && conn->get<bool>())) {
    if (pilot_ == client) pilot_lost(now, *pilot_released_);
    return;
  }
  const json* axes = member(j, "axes");
  bool ok = axes && axes->is_array() && axes->size() <= 16;
  std::array<double, 16> x{};
  std::size_t n = 0;
  if (ok) {
    for (const auto& v : *axes) {
      const double a = v.is_number() ? v.get<double>() : NAN;
      if (!(std::isfinite(a) && std::fabs(a) <= 1.0)) {
        ok = false;
        break;
      }
      x[n++] = a;
    }
  }
  if (!ok) {
    if (pilot_ == client) pilot_lost(now, *bad_gamepad_);
    refuse(client, "gamepad", *bad_gamepad_,
           "gamepad: expected \"axes\": at most 16 numbers in [-1, 1] (neutral sent)");
    return;
  }
  const bool was_pilot = pilot_ == client;
  pilot_ = client;
  pilot_rx_ = now;
  std::array<double, 6> d{};
  bool reported = true, inside = true;
  for (const GamepadAxis& a : p_.axes) {
    if (static_cast<std::size_t>(a.axis) >= n) {
      reported = false;  // an axis never reported is not centred
      continue;
    }
    const double s = shape_axis(x[static_cast<std::size_t>(a.axis)], a.deadzone, a.expo);
    if (s != 0.0) inside = false;
    d[static_cast<std::size_t>(a.dof)] += a.sign * s * a.gain;
  }
  if (was_pilot && centred_ && !reported) {
    pilot_lost(now, *bad_gamepad_);  // an axis went away: centre again
    return;
  }
  if (!centred_) centred_ = reported && inside;
  if (!centred_) {
    demand_.fill(0.0);
    publish_demand(now, false);
    return;
  }
  for (std::size_t i = 0; i < 6; ++i) demand_[i] = std::clamp(d[i] * p_.gamepad_gain, -1.0, 1.0);
  publish_demand(now, true);
}

void CockpitNode::on_thruster_test(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  const json* active = member(j, "active");
  const json* press = member(j, "press");
  if (!active || !active->is_boolean() || !press || !press->is_number_integer()) {
    refuse(client, "thruster_test", *bad_command_,
           "thruster_test: expected \"press\" (an integer) and \"active\" (true or false)");
    return;
  }
  const json* th = member(j, "thruster");
  const json* c = member(j, "command");
  const json* confirm = member(j, "confirm");
  const std::int64_t t = th && th->is_number_integer() ? th->get<std::int64_t>() : -1;
  const auto r = test_.request(client, press->get<std::int64_t>(), active->get<bool>(),
                               confirm && confirm->is_boolean() && confirm->get<bool>(),
                               t >= 0 && t <= 15 ? static_cast<int>(t) : -1,
                               c && c->is_number() ? c->get<double>() : NAN, next_id(now), now);
  using R = ThrusterTestRelay::Result;
  if (r == R::kStarted || r == R::kHeld || r == R::kEnded)
    publish(channels::kThrusterTest, test_.message());
  if (r == R::kRefused || (r == R::kEnded && test_.why()[0] != '\0')) {
    refuse(client, "thruster_test", *test_refused_, test_.why());
  } else if (r == R::kStarted) {
    ++*accepted_;
    char buf[112];
    std::snprintf(buf, sizeof buf,
                  "thruster %d at %+.2f requested (test id %lld); the mixer's gate decides",
                  test_.message().thruster, test_.message().command,
                  static_cast<long long>(test_.message().test_id));
    reply(client, "thruster_test", true, buf);
  } else if (r == R::kEnded) {
    reply(client, "thruster_test", true, "thruster test ended");
  }
}

}  // namespace tiller::cockpit
