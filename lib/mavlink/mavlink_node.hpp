// tiller-mavlink's logic: a MAVLink 2 ground station (QGroundControl, Cockpit) on one side, the
// vehicle's LCM channels on the other. Pure: frames and messages in with the time they arrived,
// frames (through the sink) and messages (through the node's publications) out; no socket, no
// clock (apps/mavlink carries the bytes). The bridge is never a second path to the ESCs: what a
// station asks becomes the same LCM messages a teleop station or the cockpit sends, under the
// same rules (docs/safety.md "Command authority"), and the mixer's intent gate and tiller-esc's
// arm latch decide.
//
// Frames in (on_bytes): parsed by the generated library (mavlink/frame.hpp). Counted and dropped,
// never acted on: bad CRC or unknown message id (rejected.frame.crc), MAVLink 1
// (rejected.frame.mavlink1), a bad or replayed signature (rejected.frame.signature, .replay),
// unsigned while signing is required (rejected.frame.unsigned), a frame for another system
// (ignored.other_target). A frame from a system other than SYSID_MYGCS (the one station obeyed)
// may read (parameters, the mission) but not command: COMMAND_ACK DENIED, a STATUSTEXT,
// rejected.frame.other_station.
// Telemetry (frames out, each at its interval, REQUEST_DATA_STREAM / SET_MESSAGE_INTERVAL change
// it): HEARTBEAT 1 Hz (SURFACE_BOAT or SUBMARINE, autopilot GENERIC, SAFETY_ARMED from
// TILLER_ARM_STATE, custom_mode = TILLER_MODE's controller_mode_t), SYS_STATUS, BATTERY_STATUS
// (TILLER_POWER), GLOBAL_POSITION_INT and VFR_HUD (TILLER_ODOMETRY about TILLER_DATUM),
// ATTITUDE, GPS_RAW_INT (TILLER_GNSS), SERVO_OUTPUT_RAW (TILLER_ESC_OUTPUT, 1500 +- 400 us per
// normalised command); STATUSTEXT for every refusal (the arm state's reason, the bridge's own)
// and every failsafe (TILLER_VEHICLE_STATUS).
// Commands: COMPONENT_ARM_DISARM (400) -> TILLER_ARM_REQUEST (station, boot nonce of the latest
// arm state; tiller-esc decides, its reason comes back as a STATUSTEXT); DO_SET_MODE (176) and
// SET_MODE -> TILLER_MODE; NAV_RETURN_TO_LAUNCH (20) -> a path home (the datum) + WAYPOINTING +
// START; MISSION_START (300) -> the uploaded mission's path + WAYPOINTING + START;
// SET_MESSAGE_INTERVAL (511), REQUEST_MESSAGE (512), REQUEST_AUTOPILOT_CAPABILITIES (520).
// MANUAL_CONTROL -> TILLER_MANUAL_DEMAND (x surge, y sway, z heave about z_centre for a
// submarine, r yaw; each /1000, deadzone, gain), published as it arrives; neutral and invalid
// until a centred stick, and again after MAN_TIMEOUT without one (then centre again).
// SETUP_SIGNING (256): mavlink_setup_signing.cpp.
// Parameters: mavlink/mavlink_params.hpp (the bridge's), then mavlink/mavlink_gains.hpp (the
// controllers' gains: a set is kept by the bridge, not applied; counted as params.gains_set).
// Missions: mavlink_mission.cpp. Sources: mavlink_node.cpp (frames, LCM in, telemetry),
// mavlink_commands.cpp (commands, manual control, parameters), mavlink_mission.cpp (the mission
// protocol).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/vehicle_status_t.hpp>

#include "mavlink/frame.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mission/sequencer.hpp"
#include "runtime/node.hpp"

namespace tiller::mavlink {

class MavlinkNode : public Node {
 public:
  // Where frames go: the bytes of one frame.
  using Sink = std::function<void(const std::uint8_t* data, std::size_t n)>;
  struct MissionItem {
    std::uint16_t command = 0;
    std::uint8_t frame = 0;
    float params[4] = {0, 0, 0, 0};
    std::int32_t x = 0, y = 0;  // degE7
    float z = 0;
    bool autocontinue = true;
  };
  static constexpr int kMissionTypes = 3;  // MAV_MISSION_TYPE_MISSION, FENCE, RALLY

  explicit MavlinkNode(MavlinkParams p);
  void set_sink(Sink s) { sink_ = std::move(s); }
  // Where a secret SETUP_SIGNING set is saved (apps/mavlink: signing.key_file); returns false
  // when it could not be. None: the new secret lasts until the bridge stops.
  using KeySink = std::function<bool(const Secret& secret)>;
  void set_key_sink(KeySink s) { key_sink_ = std::move(s); }
  // Bytes from the ground station: a whole UDP datagram (datagram: a partial frame is not carried
  // over) or a piece of a serial stream.
  void on_bytes(const std::uint8_t* data, std::size_t n, bool datagram, TimeUs now);
  void shutdown(TimeUs now) override;
  // The link's own count of frames it dropped whole (a serial radio's write queue full:
  // apps/mavlink SerialLink), shown as the heartbeat counter link.frames_dropped.
  void set_link_frames_dropped(std::int64_t total) { *link_dropped_ = total; }

  // For tests.
  double param(std::size_t i) const { return p_.params[i]; }
  const std::vector<GainParam>& gains() const { return p_.gains; }
  const std::vector<MissionItem>& mission(int type) const { return stored_[type]; }
  bool pilot_centred() const { return centred_; }
  TimeUs interval(std::uint32_t msgid) const;

 protected:
  void on_tick(TimeUs now) override;

 private:
  struct Stream {
    std::uint32_t msgid;
    TimeUs interval;  // us; <= 0: off
    TimeUs next;
  };
  struct Upload {
    bool active = false;
    std::uint8_t type = 0, sysid = 0, compid = 0;
    std::uint16_t count = 0, next = 0;
    TimeUs asked = 0;
    int retries = 0;
    std::vector<MissionItem> items;
  };

  // LCM in
  void on_arm_state(const arm_state_t& m, TimeUs now);
  void on_mode(const controller_mode_t& m, TimeUs now);
  void on_odometry(const odometry_t& m, TimeUs now);
  void on_datum(const datum_t& m, TimeUs now);
  void on_power(const power_t& m, TimeUs now);
  void on_gnss(const gnss_fix_t& m, TimeUs now);
  void on_esc_output(const esc_output_t& m, TimeUs now);
  void on_vehicle_status(const vehicle_status_t& m, TimeUs now);
  // frames
  void on_frame(const FrameReader::Frame& f, TimeUs now);
  void dispatch(const mavlink_message_t& msg, TimeUs now);
  void send(mavlink_message_t& msg, TimeUs now);
  void send_stream(std::uint32_t msgid, TimeUs now);
  void statustext(std::uint8_t severity, const std::string& text, TimeUs now);
  bool from_gcs(const mavlink_message_t& msg, TimeUs now);  // else refused, told, counted
  // commands (mavlink_commands.cpp)
  void on_command(const mavlink_message_t& msg, std::uint16_t cmd, const float (&prm)[7],
                  TimeUs now);
  void ack(const mavlink_message_t& msg, std::uint16_t cmd, std::uint8_t result, TimeUs now);
  void arm(bool arm, TimeUs now);
  void set_mode(std::int8_t mode, TimeUs now);
  void start_path(const std::vector<std::array<double, 2>>& points, TimeUs now);
  void on_manual_control(const mavlink_message_t& msg, TimeUs now);
  void publish_demand(bool valid, TimeUs now);
  void on_param(const mavlink_message_t& msg, TimeUs now);
  void send_param(std::size_t i, TimeUs now);
  std::size_t param_count() const;  // kParams, then the gains
  void set_interval(std::uint32_t msgid, double interval_us);
  void on_data_stream(const mavlink_message_t& msg);
  void on_setup_signing(const mavlink_message_t& msg, TimeUs now);  // mavlink_setup_signing.cpp
  // missions (mavlink_mission.cpp)
  void on_mission(const mavlink_message_t& msg, TimeUs now);
  void request_item(TimeUs now);
  void upload_done(TimeUs now);
  void send_item(const mavlink_message_t& req, std::uint16_t seq, std::uint8_t type, TimeUs now);
  void mission_ack(std::uint8_t sysid, std::uint8_t compid, std::uint8_t type, std::uint8_t result,
                   TimeUs now);
  void mission_tick(TimeUs now);
  // flying the uploaded mission (mavlink_fly.cpp)
  bool build_flight(std::string& why);
  void begin_flight(TimeUs now);
  void fly(mission::Sequencer::Action a, TimeUs now);
  void end_flight();
  void on_progress(const path_progress_t& m, TimeUs now);

  MavlinkParams p_;
  FrameWriter writer_;
  FrameReader reader_;
  std::optional<SignatureChecker> checker_;
  Sink sink_;
  KeySink key_sink_;
  bool frame_signed_ = false;  // the frame being dispatched was signed and verified
  std::uint8_t out_[kMaxFrame] = {};
  std::vector<Stream> streams_;
  // the vehicle, as last heard
  arm_state_t arm_{};
  std::string last_arm_reason_;
  std::int8_t mode_ = controller_mode_t::MANUAL_OPEN_LOOP;
  bool have_odom_ = false, have_datum_ = false, have_power_ = false, have_gnss_ = false;
  odometry_t odom_{};
  datum_t datum_{};
  power_t power_{};
  gnss_fix_t gnss_{};
  std::array<std::uint16_t, 16> servo_{};
  int n_servo_ = 0;
  double throttle_ = 0;
  std::int32_t failsafe_active_ = 0;
  std::string failsafe_reason_;
  // the pilot (MANUAL_CONTROL)
  bool centred_ = false;
  TimeUs pilot_rx_ = -1;
  manual_demand_t demand_{};
  // missions
  std::array<std::vector<MissionItem>, kMissionTypes> stored_;
  Upload up_;
  std::uint16_t current_ = 0;
  std::unique_ptr<mission::Mission> flight_;  // the mission in flight (metres about the datum)
  std::unique_ptr<mission::Sequencer> seq_;   // flying flight_
  std::string flight_status_;
  std::int64_t flight_base_ = 0;  // the first leg's path_id
  path_t leg_path_{};
  path_speed_t leg_speed_{};
  std::int64_t last_id_ = 0;
  std::int64_t* link_dropped_ = nullptr;
  // counters
  std::int64_t *bad_crc_, *v1_, *bad_sig_, *replay_, *unsigned_, *other_station_, *other_target_;
  std::int64_t *frames_ok_, *bad_check_, *bad_manual_, *pilot_timeout_, *param_refused_;
  std::int64_t *mission_refused_, *commands_, *commands_refused_, *unknown_, *gains_changed_;
  std::int64_t *signing_refused_, *signing_set_;
};

// The stored mission, fence and rally sets as one QGroundControl .plan text (the format
// mission::parse_plan reads; DO_JUMP's target seq k as doJumpId k + 1).
std::string plan_text(const std::array<std::vector<MavlinkNode::MissionItem>, 3>& sets);

}  // namespace tiller::mavlink
