// tiller-tune's input: a log's messages turned into identify()'s Record (identify.hpp).
// Motion: TILLER_GROUND_TRUTH when the log has it (a simulated run), else TILLER_ODOMETRY
// (needs VALID_VELOCITY and VALID_ATTITUDE; others dropped, counted), at the message's utime.
// Wrench targets: each TILLER_ESC_OUTPUT's normalised channel values (what went on the bus, as
// the hardware sees it) back to Tiller's command (a reversed thruster's sign undone), through
// the vehicle's thrust curve to a thrust (N) and through its geometry to [X Y Z K M N]; not
// armed: zero. A channel the vehicle does not name, a wrong count or a non-finite value drops
// that message (counted). Time: s from the first kept message.
#pragma once

#include <string>
#include <vector>

#include "runtime/event.hpp"
#include "tune/identify.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller::tune {

struct RecordStats {
  std::string motion_channel;  // the channel the motion came from
  int motion = 0, esc = 0;     // kept
  int dropped_motion = 0, dropped_esc = 0;
};

Record record_from_events(const std::vector<Event>& events, const Vehicle& vehicle,
                          RecordStats* stats = nullptr);

// The channels record_from_events reads (a regex for read_log).
inline constexpr const char* kRecordChannels =
    "TILLER_GROUND_TRUTH|TILLER_ODOMETRY|TILLER_ESC_OUTPUT";

}  // namespace tiller::tune
