// CockpitNode's commands from the page: the token rule (checked first, in constant time; nothing
// else is read without it) and the commands arm, mode and mission, each checked and sent once on
// its Tiller channel (signed by the transport, sender "cockpit"). A mission's upload and its items
// are in cockpit_mission.cpp, the gamepad and the thruster test in cockpit_pilot.cpp. The rules:
// cockpit/cockpit_node.hpp; the protocol: docs/reference/cockpit-api.md.
#include <sodium.h>

#include <algorithm>
#include <exception>
#include <string>
#include <utility>

#include <tiller/arm_request_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/mission_command_t.hpp>

#include "cockpit/cockpit_node_parts.hpp"
#include "runtime/channels.hpp"

namespace tiller::cockpit {

using nlohmann::json;

bool CockpitNode::refuse(int client, std::string_view command, std::int64_t& counter,
                         const std::string& why) {
  reject(counter);
  reply(client, command, false, why);
  return false;
}

void CockpitNode::command(int client, std::string_view text, TimeUs now) {
  reply_id_.clear();
  const json j = json::parse(text.begin(), text.end(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    refuse(client, "", *bad_command_, "not a JSON object");
    return;
  }
  if (const json* id = member(j, "id"); id && (id->is_number() || id->is_string()))
    reply_id_ = id->dump(-1, ' ', true, json::error_handler_t::replace);
  const json* type = member(j, "type");
  const std::string cmd = type && type->is_string() ? type->get<std::string>() : "";
  // The token first: nothing else is looked at without it.
  const json* tok = member(j, "token");
  const std::string* given = tok && tok->is_string() ? tok->get_ptr<const std::string*>() : nullptr;
  if (!given || given->size() != token_.size() || token_.empty() ||
      sodium_memcmp(given->data(), token_.data(), token_.size()) != 0) {
    refuse(client, cmd, *bad_token_, "refused: missing or wrong token (counted)");
    return;
  }
  if (cmd == "gamepad") {
    on_gamepad(client, &j, now);
    return;
  }
  if (cmd == "thruster_test") {
    on_thruster_test(client, &j, now);
    return;
  }
  if (cmd == "arm") {
    on_arm(client, &j, now);
    return;
  }
  if (cmd == "mode") {
    on_mode(client, &j, now);
    return;
  }
  if (cmd == "mission_load") {
    on_mission_load(client, &j, now);
    return;
  }
  if (cmd == "mission") {
    on_mission(client, &j, now);
    return;
  }
  refuse(client, cmd, *bad_command_,
         "unknown command type '" + cmd +
             "' (expected arm, mode, mission_load, mission, gamepad or thruster_test)");
}

void CockpitNode::on_arm(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  const std::string_view cmd = "arm";
  const json* arm = member(j, "arm");
  if (!arm || !arm->is_boolean()) {
    refuse(client, cmd, *bad_command_, "arm: expected \"arm\": true or false");
    return;
  }
  const json* confirm = member(j, "confirm");
  if (arm->get<bool>() && !(confirm && confirm->is_boolean() && confirm->get<bool>())) {
    refuse(client, cmd, *bad_command_,
           "arm: needs \"confirm\": true (the page asks the operator first)");
    return;
  }
  arm_request_t a{};
  a.utime = now;
  a.arm = arm->get<bool>();
  a.source = "cockpit";
  a.station = p_.station;
  a.boot_nonce = boot_nonce_;
  const json* takeover = member(j, "takeover");
  a.takeover = a.arm && takeover && takeover->is_boolean() && takeover->get<bool>();
  publish(channels::kArmRequest, a);
  ++*accepted_;
  reply(client, cmd, true, a.arm ? "arm request sent" : "disarm request sent");
}

void CockpitNode::on_mode(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  const std::string_view cmd = "mode";
  const json* mode = member(j, "mode");
  const std::string m = mode && mode->is_string() ? mode->get<std::string>() : "";
  // Every controller_mode_t constant (the ROV modes go to tiller-rov-control).
  static constexpr std::pair<const char*, std::int8_t> kModes[] = {
      {"MANUAL_OPEN_LOOP", controller_mode_t::MANUAL_OPEN_LOOP},
      {"MANUAL_CLOSED_LOOP", controller_mode_t::MANUAL_CLOSED_LOOP},
      {"WAYPOINTING", controller_mode_t::WAYPOINTING},
      {"STABILISE", controller_mode_t::STABILISE},
      {"DEPTH_HOLD", controller_mode_t::DEPTH_HOLD},
      {"HEADING_HOLD", controller_mode_t::HEADING_HOLD},
      {"RATE", controller_mode_t::RATE},
      {"SURFACE", controller_mode_t::SURFACE},
      {"POSITION_HOLD", controller_mode_t::POSITION_HOLD},
      {"DEPTH_HEADING_HOLD", controller_mode_t::DEPTH_HEADING_HOLD}};
  controller_mode_t c{};
  bool known = false;
  for (const auto& [name, value] : kModes) {
    if (m == name) {
      c.mode = value;
      known = true;
    }
  }
  if (!known) {
    refuse(client, cmd, *bad_command_,
           "mode: expected one of MANUAL_OPEN_LOOP, MANUAL_CLOSED_LOOP, WAYPOINTING, STABILISE, "
           "DEPTH_HOLD, HEADING_HOLD, RATE, SURFACE, POSITION_HOLD, DEPTH_HEADING_HOLD");
    return;
  }
  const json* tr = member(j, "is_translation");
  c.is_translation = tr && tr->is_boolean() && tr->get<bool>();
  c.utime = now;
  c.source = "cockpit";
  publish(channels::kMode, c);
  ++*accepted_;
  reply(client, cmd, true, "mode " + m + " sent");
}

void CockpitNode::on_mission(int client, const void* jp, TimeUs now) {
  const json& j = *static_cast<const json*>(jp);
  const std::string_view cmd = "mission";
  const json* what = member(j, "command");
  const std::string c = what && what->is_string() ? what->get<std::string>() : "";
  mission_command_t mc{};
  if (c == "start") {
    if (!gate_.open(now)) {
      refuse(client, cmd, *not_ready_,
             std::string("start refused: the estimate is not ready: ") + gate_.why(now));
      return;
    }
    mc.command = mission_command_t::START;
  } else if (c == "pause") {
    mc.command = mission_command_t::PAUSE;
  } else if (c == "resume") {
    mc.command = mission_command_t::RESUME;
  } else if (c == "abort") {
    mc.command = mission_command_t::ABORT;
  } else if (c == "release") {
    mc.command = mission_command_t::RELEASE;
  } else {
    refuse(client, cmd, *bad_command_,
           "mission: expected \"command\": start, pause, resume, abort or release");
    return;
  }
  mc.utime = now;
  mc.command_id = next_id(now);
  mc.source = "cockpit";
  publish(channels::kMissionCommand, mc);
  if (mc.command == mission_command_t::ABORT || mc.command == mission_command_t::RELEASE)
    end_mission();
  if (mc.command == mission_command_t::RELEASE) {
    arm_request_t a{};
    a.utime = now;
    a.arm = false;
    a.source = "cockpit (release)";
    a.station = p_.station;
    publish(channels::kArmRequest, a);
  }
  ++*accepted_;
  reply(client, cmd, true, c + " sent (id " + std::to_string(mc.command_id) + ")");
}

}  // namespace tiller::cockpit
