// tiller-log's csv, fields and restamp commands on a log already read (log_io.hpp): what they
// print and their exit status (0 done, 1 nothing to show, 2 a --fields name that chooses nothing).
// Messages go to `out`, problems to `err` as "tiller-log: ..." lines.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

// "CHANNEL: type" then "  path = value" for each field of the channel's first message.
int print_fields(const std::vector<Event>& events, const std::string& channel, std::ostream& out,
                 std::ostream& err);

// One CSV row per message of `events` (the channel's), times from the log's first event `t0`,
// to `out` or, when `output` is not empty, to that file. Every name in `fields` must choose a
// field of the channel's messages (csv.hpp: path or prefix); else the list of its fields.
int export_csv(const std::vector<Event>& events, const std::string& channel,
               const std::vector<std::string>& fields, TimeUs t0, const std::string& output,
               std::ostream& out, std::ostream& err);

// Moves `events` in time by `shift` us: every event's time and, in every message of a Tiller
// type (each begins with `int64_t utime` after its fingerprint: lcmtypes/), that utime. Messages
// of other types keep their bytes. Returns how many utimes it moved.
std::size_t shift_times(std::vector<Event>& events, TimeUs shift);

// restamp: writes `events` to `output` moved so that the first event is at `start` (the caller's
// clock, us since the epoch). A log played into live processes with lcm-logplayer must be
// restamped first: every node refuses a message whose utime is older than its input's freshness
// limit plus the clock offset bound (docs/safety.md, "Stalls and liveness"). Signatures are not
// kept (read_log strips them; a changed utime would not verify anyway).
int restamp_log(std::vector<Event> events, TimeUs start, const std::string& output,
                std::ostream& out, std::ostream& err);

}  // namespace tiller::logtools
