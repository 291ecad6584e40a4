// tiller-mission's logic: publishes a mission's path on TILLER_PATH and TILLER_MODE (waypointing,
// with the mission's is_translation) at its first tick and again every repeat period (state: a
// repeat of the same path_id does not restart the follower; it covers lost packets and late
// starters). The operator's intent is sent as events, once each (docs/safety.md):
//   * one arm request on TILLER_ARM_REQUEST once the path is out and a TILLER_ARM_STATE has
//     given tiller-esc's boot nonce (unless arm = false), never repeated, so a vehicle disarmed
//     by a timeout or a restart stays disarmed;
//   * one START on TILLER_MISSION_COMMAND (command_id = path_id) when TILLER_ARM_STATE first says
//     armed: the mixer's safety gate lets the autonomy move the vehicle only after it.
// With a start gate (mission/start_gate.hpp, `gate.enabled`) it subscribes to TILLER_ODOMETRY and
// publishes nothing, not even the path or the arm request, until the gate first opens (the
// estimate valid, certain to gate.max_position_std_m and settled for gate.settle_s); the
// heartbeat says "waiting for the estimate: ..." meanwhile; it ticks every 100 ms (or the repeat
// period if shorter) to watch the gate, and repeats the path every repeat period after its start.
// Once started it does not wait again: a later bad estimate is the controllers' and the failsafe's
// to act on (docs/safety.md).
// A mission with items (loiter, return home, stop, speed, jump, fence; mission/sequencer.hpp)
// is flown as legs: each leg a new path_id (path_id, path_id + 1, ...), published when it
// begins and repeated like a plain path, each time after its speeds (TILLER_PATH_SPEED,
// path_speed_t: the legs' speed changes, 0 = the follower's max_speed); it subscribes
// TILLER_PATH_PROGRESS (a leg complete) and TILLER_ODOMETRY (where the first leg starts, the
// run-time fence). Hold is an operator ABORT, stop an operator RELEASE (the mixer disarms), each
// sent once (command ids from path_id + kCommandIdOffset); the heartbeat's status says what the
// mission does (DEGRADED after a fence breach, counted in fence.breaches).
// With datum_from_vehicle, a mission in lat/lon publishes nothing until the first TILLER_DATUM
// (datum_t, from tiller-nav: the frame its odometry is in), then is converted about it
// (mission::relocalise) and goes on as above; a later, different datum is ignored and counted in
// datum.later_ignored (the mission keeps the frame it started in). A mission in metres ignores it.
#pragma once

#include <tiller/arm_state_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>

#include <memory>
#include <string>

#include "mission/mission.hpp"
#include "mission/sequencer.hpp"
#include "mission/start_gate.hpp"
#include "runtime/node.hpp"

namespace tiller::mission {

class MissionNode : public Node {
 public:
  MissionNode(const Mission& m, std::int64_t path_id, TimeUs repeat_period_us, bool arm = true,
              const StartGateParams& gate = {}, bool datum_from_vehicle = false);
  bool waiting_for_datum() const { return waiting_datum_; }
  void on_tick(TimeUs now) override;
  int sent() const { return sent_; }
  bool started() const { return start_sent_; }
  // The time of the first tick that published the path (-1 while waiting for the estimate).
  TimeUs began_at() const { return began_at_; }
  // Items: the sequencer (nullptr for a plain path).
  const Sequencer* sequencer() const { return seq_.get(); }
  static constexpr std::int64_t kCommandIdOffset = 1'000'000;

 private:
  void on_arm_state(const arm_state_t& m, TimeUs now);
  void on_datum(const datum_t& m, TimeUs now);
  void on_odometry(const odometry_t& m, TimeUs now);
  void on_progress(const path_progress_t& m, TimeUs now);
  void act(Sequencer::Action a, TimeUs now);
  void publish_path(TimeUs now);
  void maybe_arm(TimeUs now);  // the --arm request, once the path is out and an arm state seen
  void send_command(std::int8_t command, TimeUs now);

  static constexpr TimeUs kGatePollUs = 100'000;  // gated: the tick that watches the gate

  TimeUs repeat_us_;
  TimeUs last_sent_ = 0;
  path_t path_;
  bool translation_;
  bool arm_;
  bool arm_sent_ = false;
  bool path_sent_ = false;
  bool have_arm_state_ = false;  // a TILLER_ARM_STATE seen: its boot nonce is known
  std::int64_t boot_nonce_ = 0;  // the arm request carries it
  bool start_sent_ = false;
  int sent_ = 0;
  std::string name_;
  StartGate gate_;
  TimeUs began_at_ = -1;
  TimeUs status_at_ = -1;  // when the "waiting" status was last written
  // Items.
  std::unique_ptr<Mission> mission_;
  std::unique_ptr<Sequencer> seq_;
  std::int64_t base_id_ = 0;
  std::int64_t commands_sent_ = 0;
  bool have_position_ = false;
  MissionPoint position_;
  std::int64_t* fence_breaches_ = nullptr;
  path_speed_t speed_{};
  std::string shown_status_;  // the sequencer's status last put in the heartbeat
  // datum_from_vehicle: a lat/lon mission waits for TILLER_DATUM, then is converted about it.
  bool waiting_datum_ = false;
  GeoPoint datum_used_;
  std::int64_t* datum_ignored_ = nullptr;
};

}  // namespace tiller::mission
