// CockpitNode's private pieces shared by its source files (not part of the API): the state slots
// (the latest checked message of each state channel), the heartbeat of each configured process,
// and member(), the one way a command's JSON field is looked up.
//   cockpit_node.cpp      subscriptions, counters, the tick, the clients coming and going
//   cockpit_frames.cpp    the frames to the browser: hello, state / snapshot, reply
//   cockpit_commands.cpp  the token rule and the commands arm, mode, mission_load, mission
//   cockpit_pilot.cpp     the gamepad as a pilot source, and the thruster test requests
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include <tiller/heartbeat_t.hpp>

#include "cockpit/cockpit_node.hpp"
#include "cockpit/json_writer.hpp"
#include "cockpit/lcm_json.hpp"

namespace tiller::cockpit {

struct CockpitNode::SlotBase {
  virtual ~SlotBase() = default;
  virtual void write(JsonWriter& w) const = 0;
  std::string channel;
  TimeUs rx = -1;  // receive time of the latest good message; -1: none yet
  bool dirty = false;
  std::int64_t* bad = nullptr;
};

template <class Msg>
struct CockpitNode::Slot : SlotBase {
  Msg msg{};
  void write(JsonWriter& w) const override { to_json(w, msg); }
};

struct CockpitNode::Process {
  std::string name, channel;
  heartbeat_t hb{};
  TimeUs rx = -1;
  bool dirty = false;
};

// j[key], or nullptr when j has no such member.
inline const nlohmann::json* member(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

}  // namespace tiller::cockpit
