// tiller-cockpit's logic: the vehicle's state channels in, JSON frames for the browser out, and
// the page's commands out as ordinary Tiller commands. Pure: no socket, no clock, no file (the
// server glue, cockpit/server.hpp, carries the frames; a mission's text is parsed by the
// injected loader).
//
// State: the latest message of each state channel (state_channels()) and the heartbeat of each
// configured process, each checked (core/message_checks.hpp; a bad one is dropped and counted in
// rejected.<channel>.check). Every period (rate_hz) the node sends a "state" frame to every
// client with the channels that changed since the last frame (latest value only: a 100 Hz
// channel costs one entry per frame), the health of every process (SILENT when its heartbeat is
// older than silent_after_s or never came) and the pilot's demand. A new client first gets
// "hello" (constants, the process list, the gamepad mapping) and a full snapshot.
// JSON for every LCM type comes from cockpit/lcm_json.hpp, generated at build time from
// lcmtypes/ (tools/lcm-json.py). The protocol: docs/reference/cockpit-api.md.
//
// Commands: every command carries the token (compared in constant time, sodium_memcmp); one
// without it, or with another, is refused, answered with ok=false and counted in
// rejected.command.token (so in the heartbeat). Accepted commands go out through the node's
// publications, signed by the transport like every node's (sender "cockpit"):
//   arm (needs confirm: true) / disarm   -> TILLER_ARM_REQUEST, once
//   mode                                 -> TILLER_MODE, once
//   mission_load (YAML, CSV or .plan text) -> TILLER_PATH (new path_id; repeated every
//                                           path_repeat_s until abort/release) + TILLER_MODE
//                                           WAYPOINTING, once; with items, leg by leg with
//                                           TILLER_PATH_SPEED (cockpit_mission.cpp); in lat/lon
//                                           about TILLER_DATUM; a "mission" frame for the map
//   mission start/pause/resume/abort/release -> TILLER_MISSION_COMMAND (a new command_id each);
//                                           release also a disarm request; with start_gate a
//                                           start is refused (rejected.mission.not_ready) while
//                                           the odometry fails mission/start_gate.hpp's test
//   gamepad (axes of the browser's Gamepad API) -> TILLER_MANUAL_DEMAND
//   thruster_test (hold-to-spin, needs confirm) -> TILLER_THRUSTER_TEST (cockpit/thruster_test.hpp)
// The cockpit never publishes thruster commands (a thruster test is a request to the mixer's gate):
// thrust comes only through tiller-mixer's intent gate (lib/safety/intent_gate.hpp), which needs a
// centred stick after every arming and every loss, exactly as for tiller-teleop. The gamepad
// follows tiller-teleop's rules: one page at a time is the pilot (another page's gamepad is
// refused, rejected.gamepad.other_pilot); its demand is neutral and invalid until every mapped axis
// has been reported and seen inside its deadzone; the page sends its axes every 50 ms while it is
// visible. A page that says it lost its gamepad or was hidden (connected: false), closes its socket
// (client_closed), sends a bad value, or is silent for gamepad.timeout_s gives a neutral, invalid
// demand at once and must centre again; the mixer's freshness limit covers a lost packet.
// shutdown() sends the same neutral, invalid demand.
// Sources: cockpit_node.cpp (subscriptions, tick, clients), cockpit_frames.cpp (the JSON frames),
// cockpit_commands.cpp (token, arm, mode, missions), cockpit_pilot.cpp (gamepad, thruster test).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>

#include "cockpit/cockpit_config.hpp"
#include "cockpit/thruster_test.hpp"
#include "mission/mission.hpp"
#include "mission/sequencer.hpp"
#include "runtime/node.hpp"

namespace tiller::cockpit {

// The state channels the cockpit shows (besides the configured heartbeats).
const std::vector<std::string>& state_channels();

class CockpitNode : public Node {
 public:
  // Where a frame goes besides one client: kAllClients is latest-value (the state frame: one not
  // yet sent is replaced by the next); kEveryClient is queued for each page like a reply, never
  // replaced (the mission frame, which is sent once per load).
  static constexpr int kAllClients = -1;
  static constexpr int kEveryClient = -2;
  // Where frames go: (client id, kAllClients or kEveryClient, one JSON text).
  using Sink = std::function<void(int client, const std::string& json)>;
  // Parses a mission file's text ("name" says .yaml/.yml, .csv or .plan), lat/lon converted to
  // metres about the datum when one is given; throws config::Error with the line and key.
  using MissionLoader =
      std::function<mission::Mission(const std::string& name, const std::string& text,
                                     const std::optional<mission::GeoPoint>& datum)>;

  CockpitNode(CockpitParams p, std::string token, MissionLoader loader);
  ~CockpitNode() override;

  void set_sink(Sink s) { sink_ = std::move(s); }
  // A page connected: it gets hello and a full snapshot.
  void client_opened(int client, TimeUs now);
  // A page's socket closed: if it was the pilot, neutral at once.
  void client_closed(int client, TimeUs now);
  // One text message from a page.
  void command(int client, std::string_view text, TimeUs now);
  void shutdown(TimeUs now) override;

  // For tests.
  int pilot_client() const { return pilot_; }
  bool pilot_centred() const { return centred_; }
  const std::array<double, 6>& demand() const { return demand_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  struct SlotBase;
  template <class Msg>
  struct Slot;
  struct Process;

  template <class Msg, int I>
  void on_state(const Msg& m, TimeUs now);
  void on_heartbeat(const heartbeat_t& m, TimeUs now);
  void write_hello(int client);
  void write_state(TimeUs now, bool full);
  void reply(int client, std::string_view command, bool ok, const std::string& detail);
  bool refuse(int client, std::string_view command, std::int64_t& counter, const std::string& why);
  // The commands (json: the command's nlohmann::json object).
  void on_arm(int client, const void* json, TimeUs now);
  void on_mode(int client, const void* json, TimeUs now);
  void on_mission_load(int client, const void* json, TimeUs now);  // cockpit_mission.cpp
  void publish_mission_path(TimeUs now);  // the speeds (items), then the path
  void fly_items(mission::Sequencer::Action a, TimeUs now);
  void on_items_odometry(const odometry_t& m, TimeUs now);
  void on_items_progress(const path_progress_t& m, TimeUs now);
  void end_mission();  // abort, release, a new upload: no more repeats, no sequencer
  void write_mission_frame(const mission::Mission& m);
  void on_mission(int client, const void* json, TimeUs now);
  void on_gamepad(int client, const void* json, TimeUs now);
  void on_thruster_test(int client, const void* json, TimeUs now);
  void pilot_lost(TimeUs now, std::int64_t& why);
  void publish_demand(TimeUs now, bool valid);
  void emit(int client);
  std::int64_t next_id(TimeUs now);

  CockpitParams p_;
  std::string token_;
  MissionLoader loader_;
  Sink sink_;
  std::vector<std::unique_ptr<SlotBase>> slots_;
  std::vector<Process> processes_;
  std::string frame_;     // reused
  std::string reply_id_;  // the command's "id", as JSON ("" = none)
  // pilot (gamepad)
  int pilot_ = -1;
  TimeUs pilot_rx_ = 0;
  bool centred_ = false;
  std::array<double, 6> demand_{};
  manual_demand_t demand_msg_{};
  std::int64_t boot_nonce_ = 0;  // the latest TILLER_ARM_STATE's: arm requests carry it
  // thruster test
  ThrusterTestRelay test_;
  // mission
  bool path_active_ = false;
  path_t path_;
  TimeUs path_sent_ = 0;
  std::int64_t last_id_ = 0;
  mission::StartGate gate_;
  std::unique_ptr<mission::Mission> items_;  // a mission with items: flown by seq_
  std::unique_ptr<mission::Sequencer> seq_;
  std::int64_t base_id_ = 0;  // legs are path_ids base_id_, base_id_ + 1, ...
  path_speed_t speed_{};
  std::string items_status_;   // the sequencer's status last put in the heartbeat
  std::string mission_frame_;  // the loaded plan for the map ("": none), sent to new pages
  bool have_datum_ = false;    // TILLER_DATUM seen: uploads in lat/lon are localised about datum_
  mission::GeoPoint datum_;
  bool have_position_ = false;  // the latest odometry with a valid position
  mission::MissionPoint position_;
  // counters
  std::int64_t* accepted_;
  std::int64_t* bad_token_;
  std::int64_t* bad_command_;
  std::int64_t* bad_gamepad_;
  std::int64_t* other_pilot_;
  std::int64_t* bad_mission_;
  std::int64_t* pilot_timeout_;
  std::int64_t* pilot_closed_;
  std::int64_t* pilot_released_;
  std::int64_t* heartbeat_unknown_;
  std::int64_t* bad_heartbeat_;
  std::int64_t* test_refused_;
  std::int64_t* not_ready_;
  std::int64_t* fence_breaches_;
};

}  // namespace tiller::cockpit
