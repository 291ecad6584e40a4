// CockpitNode's frames to the browser (docs/reference/cockpit-api.md): "hello" (the constants, the
// process list, the gamepad mapping, the thruster test's cap), "state" / "snapshot" (the changed or
// every state channel, each as {rx, msg} with msg from the generated cockpit/lcm_json.hpp, the
// health of every process, the pilot, the cockpit's own counters) and "reply" (one per command).
// Each is written into frame_ (reused) and handed to the sink by emit().
#include <tiller/heartbeat_t.hpp>

#include "cockpit/cockpit_node_parts.hpp"

namespace tiller::cockpit {

namespace {

const char* state_name(std::int8_t s) {
  switch (s) {
    case heartbeat_t::STATE_OK:
      return "OK";
    case heartbeat_t::STATE_DEGRADED:
      return "DEGRADED";
    default:
      return "FAULT";
  }
}

}  // namespace

void CockpitNode::write_hello(int client) {
  frame_.clear();
  JsonWriter w(frame_);
  w.begin_object();
  w.key("type");
  w.string("hello");
  w.key("version");
  w.number(std::int64_t{1});
  w.key("client");
  w.number(static_cast<std::int64_t>(client));
  w.key("rate_hz");
  w.number(1e6 / static_cast<double>(tick_period()));
  w.key("channels");
  w.begin_array();
  for (const auto& c : state_channels()) w.string(c);
  w.end_array();
  w.key("processes");
  w.begin_array();
  for (const auto& pr : processes_) w.string(pr.name);
  w.end_array();
  w.key("gamepad");
  w.begin_object();
  w.key("period_s");
  w.number(0.05);
  w.key("timeout_s");
  w.number(to_seconds(p_.gamepad_timeout));
  w.key("gain");
  w.number(p_.gamepad_gain);
  w.key("axes");
  w.begin_array();
  static const char* const dofs[6] = {"surge", "sway", "heave", "roll", "pitch", "yaw"};
  for (const auto& a : p_.axes) {
    w.begin_object();
    w.key("axis");
    w.number(static_cast<std::int64_t>(a.axis));
    w.key("dof");
    w.string(dofs[a.dof]);
    w.key("sign");
    w.number(a.sign);
    w.key("deadzone");
    w.number(a.deadzone);
    w.key("expo");
    w.number(a.expo);
    w.key("gain");
    w.number(a.gain);
    w.end_object();
  }
  w.end_array();
  w.end_object();
  w.key("thruster_test");
  w.begin_object();
  w.key("max_command");
  w.number(p_.thruster_test.max_command);
  w.key("period_s");
  w.number(0.1);
  w.end_object();
  w.key("constants");
  constants_json(w);
  w.end_object();
}

void CockpitNode::write_state(TimeUs now, bool full) {
  frame_.clear();
  JsonWriter w(frame_);
  w.begin_object();
  w.key("type");
  w.string(full ? "snapshot" : "state");
  w.key("t");
  w.number(now);
  w.key("msgs");
  w.begin_object();
  for (auto& s : slots_) {
    if (s->rx < 0 || !(full || s->dirty)) continue;
    w.key(s->channel);
    w.begin_object();
    w.key("rx");
    w.number(s->rx);
    w.key("msg");
    s->write(w);
    w.end_object();
    if (!full) s->dirty = false;
  }
  for (auto& pr : processes_) {
    if (pr.rx < 0 || !(full || pr.dirty)) continue;
    w.key(pr.channel);
    w.begin_object();
    w.key("rx");
    w.number(pr.rx);
    w.key("msg");
    to_json(w, pr.hb);
    w.end_object();
    if (!full) pr.dirty = false;
  }
  w.end_object();
  w.key("health");
  w.begin_array();
  for (const auto& pr : processes_) {
    const bool silent = pr.rx < 0 || now - pr.rx > p_.silent_after;
    w.begin_object();
    w.key("process");
    w.string(pr.name);
    w.key("state");
    w.string(silent ? "SILENT" : state_name(pr.hb.state));
    w.key("status");
    w.string(pr.rx < 0 ? "no heartbeat yet" : pr.hb.status);
    w.key("age_s");
    if (pr.rx < 0) {
      w.null();
    } else {
      w.number(to_seconds(now - pr.rx));
    }
    w.end_object();
  }
  w.end_array();
  w.key("pilot");
  w.begin_object();
  w.key("client");
  w.number(static_cast<std::int64_t>(pilot_));
  w.key("centred");
  w.boolean(centred_);
  w.key("demand");
  w.begin_array();
  for (double d : demand_) w.number(d);
  w.end_array();
  w.end_object();
  w.key("cockpit");
  w.begin_object();
  w.key("accepted");
  w.number(*accepted_);
  w.key("rejected");
  w.number(rejected());
  w.key("token_refused");
  w.number(*bad_token_);
  w.end_object();
  w.end_object();
}

void CockpitNode::reply(int client, std::string_view command, bool ok, const std::string& detail) {
  frame_.clear();
  JsonWriter w(frame_);
  w.begin_object();
  w.key("type");
  w.string("reply");
  w.key("command");
  w.string(command);
  w.key("id");
  if (reply_id_.empty()) {
    w.null();
  } else {
    w.raw(reply_id_);
  }
  w.key("ok");
  w.boolean(ok);
  w.key(ok ? "detail" : "error");
  w.string(detail);
  w.end_object();
  emit(client);
}

}  // namespace tiller::cockpit
