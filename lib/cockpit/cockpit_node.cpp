// CockpitNode (cockpit/cockpit_node.hpp), its frame: the state channels and heartbeats it
// subscribes, its publications and counters, the tick (pilot deadman, thruster test timeout, the
// mission path repeated, one state frame to every page) and the pages coming and going. The frames'
// JSON is in cockpit_frames.cpp, the commands in cockpit_commands.cpp and cockpit_pilot.cpp.
#include "cockpit/cockpit_node.hpp"

#include <algorithm>
#include <cctype>
#include <type_traits>
#include <utility>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>

#include "cockpit/cockpit_node_parts.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"
#include "runtime/heartbeat_name.hpp"

namespace tiller::cockpit {

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
  kGnss,
  kDatum,
  kSlots
};

std::string counter_base(std::string_view channel) {
  std::string s(channel.substr(channel.rfind("TILLER_", 0) == 0 ? 7 : 0));
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
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
                                             channels::kPidStation,
                                             channels::kGnss,
                                             channels::kDatum};
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
  if constexpr (std::is_same_v<Msg, odometry_t>) {
    gate_.on_odometry(m, now);
    on_items_odometry(m, now);
  }
  if constexpr (std::is_same_v<Msg, path_progress_t>) on_items_progress(m, now);
  if constexpr (std::is_same_v<Msg, datum_t>) {
    datum_ = {m.latitude, m.longitude, m.altitude};
    have_datum_ = true;
  }
  if constexpr (std::is_same_v<Msg, arm_state_t>) boot_nonce_ = m.boot_nonce;  // arms carry it
}

CockpitNode::CockpitNode(CockpitParams p, std::string token, MissionLoader loader)
    : Node("cockpit", p.period),
      p_(std::move(p)),
      token_(std::move(token)),
      loader_(std::move(loader)),
      test_(p_.thruster_test),
      gate_(p_.start_gate) {
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
  add(std::make_unique<Slot<gnss_fix_t>>(), kGnss, &CockpitNode::on_state<gnss_fix_t, kGnss>);
  add(std::make_unique<Slot<datum_t>>(), kDatum, &CockpitNode::on_state<datum_t, kDatum>);
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
  advertise<path_speed_t>(channels::kPathSpeed);
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
  not_ready_ = &counter("rejected.mission.not_ready");
  fence_breaches_ = &counter("fence.breaches");
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

void CockpitNode::on_tick(TimeUs now) {
  if (pilot_ >= 0 && now - pilot_rx_ > p_.gamepad_timeout) pilot_lost(now, *pilot_timeout_);
  if (test_.tick(now)) publish(channels::kThrusterTest, test_.message());
  if (seq_ && path_active_) fly_items(seq_->on_tick(now), now);
  if (path_active_ && now - path_sent_ >= p_.path_repeat) publish_mission_path(now);
  write_state(now, false);
  emit(kAllClients);
}

void CockpitNode::client_opened(int client, TimeUs now) {
  write_hello(client);
  emit(client);
  if (!mission_frame_.empty()) {
    frame_ = mission_frame_;
    emit(client);
  }
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

std::int64_t CockpitNode::next_id(TimeUs now) {
  last_id_ = std::max<std::int64_t>(now, last_id_ + 1);
  return last_id_;
}

}  // namespace tiller::cockpit
