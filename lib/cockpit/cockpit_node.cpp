#include "cockpit/cockpit_node.hpp"

#include <sodium.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <nlohmann/json.hpp>
#include <utility>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include "cockpit/lcm_json.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"
#include "runtime/heartbeat_name.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller::cockpit {

using nlohmann::json;

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

namespace {

// Indexes of the state slots, in state_channels() order.
enum : int {
  kOdom,
  kPath,
  kProgress,
  kSetpoint,
  kThrusters,
  kAllocation,
  kArm,
  kArbitration,
  kMode,
  kVehicleStatus,
  kEscOutput,
  kPidVelocity,
  kPidStation,
  kSlots
};

std::string counter_base(std::string_view channel) {
  std::string s(channel.substr(channel.rfind("TILLER_", 0) == 0 ? 7 : 0));
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

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

const json* member(const json& j, const char* key) {
  const auto it = j.find(key);
  return it == j.end() ? nullptr : &*it;
}

}  // namespace

const std::vector<std::string>& state_channels() {
  static const std::vector<std::string> c = {channels::kOdometry,
                                             channels::kPath,
                                             channels::kPathProgress,
                                             channels::kVelocitySetpoint,
                                             channels::kThrusterCommand,
                                             channels::kAllocationStatus,
                                             channels::kArmState,
                                             channels::kArbitration,
                                             channels::kMode,
                                             channels::kVehicleStatus,
                                             channels::kEscOutput,
                                             channels::kPidVelocity,
                                             channels::kPidStation};
  return c;
}

template <class Msg, int I>
void CockpitNode::on_state(const Msg& m, TimeUs now) {
  auto& s = static_cast<Slot<Msg>&>(*slots_[I]);
  if (checks::check(m) != nullptr) {
    reject(*s.bad);
    return;
  }
  s.msg = m;
  s.rx = now;
  s.dirty = true;
}

CockpitNode::CockpitNode(CockpitParams p, std::string token, MissionLoader loader)
    : Node("cockpit", p.period),
      p_(std::move(p)),
      token_(std::move(token)),
      loader_(std::move(loader)),
      test_(p_.thruster_test) {
  const auto& ch = state_channels();
  auto add = [&](auto slot, int index, auto handler) {
    slot->channel = ch[static_cast<std::size_t>(index)];
    slot->bad = &counter("rejected." + counter_base(slot->channel) + ".check");
    slots_.push_back(std::move(slot));
    subscribe(ch[static_cast<std::size_t>(index)], handler);
  };
  add(std::make_unique<Slot<odometry_t>>(), kOdom, &CockpitNode::on_state<odometry_t, kOdom>);
  add(std::make_unique<Slot<path_t>>(), kPath, &CockpitNode::on_state<path_t, kPath>);
  add(std::make_unique<Slot<path_progress_t>>(), kProgress,
      &CockpitNode::on_state<path_progress_t, kProgress>);
  add(std::make_unique<Slot<velocity_setpoint_t>>(), kSetpoint,
      &CockpitNode::on_state<velocity_setpoint_t, kSetpoint>);
  add(std::make_unique<Slot<thruster_command_t>>(), kThrusters,
      &CockpitNode::on_state<thruster_command_t, kThrusters>);
  add(std::make_unique<Slot<allocation_status_t>>(), kAllocation,
      &CockpitNode::on_state<allocation_status_t, kAllocation>);
  add(std::make_unique<Slot<arm_state_t>>(), kArm, &CockpitNode::on_state<arm_state_t, kArm>);
  add(std::make_unique<Slot<arbitration_t>>(), kArbitration,
      &CockpitNode::on_state<arbitration_t, kArbitration>);
  add(std::make_unique<Slot<controller_mode_t>>(), kMode,
      &CockpitNode::on_state<controller_mode_t, kMode>);
  add(std::make_unique<Slot<vehicle_status_t>>(), kVehicleStatus,
      &CockpitNode::on_state<vehicle_status_t, kVehicleStatus>);
  add(std::make_unique<Slot<esc_output_t>>(), kEscOutput,
      &CockpitNode::on_state<esc_output_t, kEscOutput>);
  add(std::make_unique<Slot<pid_terms_t>>(), kPidVelocity,
      &CockpitNode::on_state<pid_terms_t, kPidVelocity>);
  add(std::make_unique<Slot<pid_terms_t>>(), kPidStation,
      &CockpitNode::on_state<pid_terms_t, kPidStation>);
  for (const auto& name : p_.processes) {
    Process pr;
    pr.name = name;
    pr.channel = heartbeat_channel_of(name);
    if (std::any_of(processes_.begin(), processes_.end(),
                    [&](const Process& q) { return q.channel == pr.channel; }))
      continue;
    processes_.push_back(pr);
    subscribe(pr.channel, &CockpitNode::on_heartbeat);
  }
  advertise<manual_demand_t>(channels::kManualDemand);
  advertise<arm_request_t>(channels::kArmRequest);
  advertise<controller_mode_t>(channels::kMode);
  advertise<mission_command_t>(channels::kMissionCommand);
  advertise<path_t>(channels::kPath);
  advertise<thruster_test_t>(channels::kThrusterTest);
  bad_heartbeat_ = &counter("rejected.heartbeat.check");
  heartbeat_unknown_ = &counter("rejected.heartbeat.unknown_process");
  accepted_ = &counter("commands.accepted");
  bad_token_ = &counter("rejected.command.token");
  bad_command_ = &counter("rejected.command.malformed");
  bad_gamepad_ = &counter("rejected.gamepad.value");
  other_pilot_ = &counter("rejected.gamepad.other_pilot");
  bad_mission_ = &counter("rejected.mission.file");
  pilot_timeout_ = &counter("pilot.lost.timeout");
  pilot_closed_ = &counter("pilot.lost.closed");
  pilot_released_ = &counter("pilot.lost.released");
  test_refused_ = &counter("rejected.thruster_test.refused");
  frame_.reserve(64 * 1024);
  set_health(heartbeat_t::STATE_OK, "serving the cockpit");
}

CockpitNode::~CockpitNode() = default;

void CockpitNode::on_heartbeat(const heartbeat_t& m, TimeUs now) {
  if (checks::check(m) != nullptr) {
    reject(*bad_heartbeat_);
    return;
  }
  for (Process& pr : processes_) {
    if (pr.name != m.process) continue;
    pr.hb = m;
    pr.rx = now;
    pr.dirty = true;
    return;
  }
  reject(*heartbeat_unknown_);
}

void CockpitNode::emit(int client) {
  if (sink_) sink_(client, frame_);
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

void CockpitNode::on_tick(TimeUs now) {
  if (pilot_ >= 0 && now - pilot_rx_ > p_.gamepad_timeout) pilot_lost(now, *pilot_timeout_);
  if (test_.tick(now)) publish(channels::kThrusterTest, test_.message());
  if (path_active_ && now - path_sent_ >= p_.path_repeat) {
    path_.utime = now;
    publish(channels::kPath, path_);
    path_sent_ = now;
  }
  write_state(now, false);
  emit(kAllClients);
}

void CockpitNode::client_opened(int client, TimeUs now) {
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
  emit(client);
  write_state(now, true);
  emit(client);
}

void CockpitNode::client_closed(int client, TimeUs now) {
  if (client == pilot_) pilot_lost(now, *pilot_closed_);
  if (test_.client_closed(client, now)) publish(channels::kThrusterTest, test_.message());
}

void CockpitNode::shutdown(TimeUs now) {
  if (pilot_ >= 0) pilot_lost(now, *pilot_closed_);
  if (test_.client_closed(test_.client(), now)) publish(channels::kThrusterTest, test_.message());
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

bool CockpitNode::refuse(int client, std::string_view command, std::int64_t& counter,
                         const std::string& why) {
  reject(counter);
  reply(client, command, false, why);
  return false;
}

void CockpitNode::publish_demand(TimeUs now, bool valid) {
  demand_msg_.utime = now;
  for (int i = 0; i < 6; ++i)
    demand_msg_.demand[i] = valid ? demand_[static_cast<std::size_t>(i)] : 0.0;
  demand_msg_.valid = valid;
  publish(channels::kManualDemand, demand_msg_);
}

void CockpitNode::pilot_lost(TimeUs now, std::int64_t& why) {
  ++why;
  demand_.fill(0.0);
  centred_ = false;
  pilot_ = -1;
  publish_demand(now, false);
}

std::int64_t CockpitNode::next_id(TimeUs now) {
  last_id_ = std::max<std::int64_t>(now, last_id_ + 1);
  return last_id_;
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
    publish(channels::kArmRequest, a);
    ++*accepted_;
    reply(client, cmd, true, a.arm ? "arm request sent" : "disarm request sent");
    return;
  }
  if (cmd == "mode") {
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
        {"POSITION_HOLD", controller_mode_t::POSITION_HOLD}};
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
             "DEPTH_HOLD, HEADING_HOLD, RATE, SURFACE, POSITION_HOLD");
      return;
    }
    const json* tr = member(j, "is_translation");
    c.is_translation = tr && tr->is_boolean() && tr->get<bool>();
    c.utime = now;
    c.source = "cockpit";
    publish(channels::kMode, c);
    ++*accepted_;
    reply(client, cmd, true, "mode " + m + " sent");
    return;
  }
  if (cmd == "mission_load") {
    const json* name = member(j, "name");
    const json* body = member(j, "text");
    if (!name || !name->is_string() || !body || !body->is_string()) {
      refuse(client, cmd, *bad_command_, "mission_load: expected \"name\" and \"text\" strings");
      return;
    }
    mission::Mission m;
    try {
      m = loader_(name->get<std::string>(), body->get<std::string>());
    } catch (const std::exception& e) {
      refuse(client, cmd, *bad_mission_, e.what());
      return;
    }
    path_ = mission::to_path(m, next_id(now), now);
    path_active_ = true;
    path_sent_ = now;
    publish(channels::kPath, path_);
    controller_mode_t c{};
    c.utime = now;
    c.mode = controller_mode_t::WAYPOINTING;
    c.is_translation = m.is_translation;
    c.source = "cockpit";
    publish(channels::kMode, c);
    ++*accepted_;
    reply(client, cmd, true,
          m.name + ": " + std::to_string(m.waypoints.size()) + " waypoints, path_id " +
              std::to_string(path_.path_id) + " (mode WAYPOINTING; arm, then start)");
    return;
  }
  if (cmd == "mission") {
    const json* what = member(j, "command");
    const std::string c = what && what->is_string() ? what->get<std::string>() : "";
    mission_command_t mc{};
    if (c == "start") {
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
      path_active_ = false;
    if (mc.command == mission_command_t::RELEASE) {
      arm_request_t a{};
      a.utime = now;
      a.arm = false;
      a.source = "cockpit (release)";
      publish(channels::kArmRequest, a);
    }
    ++*accepted_;
    reply(client, cmd, true, c + " sent (id " + std::to_string(mc.command_id) + ")");
    return;
  }
  refuse(client, cmd, *bad_command_,
         "unknown command type '" + cmd +
             "' (expected arm, mode, mission_load, mission, gamepad or thruster_test)");
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
