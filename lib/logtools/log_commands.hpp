// tiller-log's csv and fields commands on a log already read (log_io.hpp): what they print and
// their exit status (0 done, 1 nothing to show, 2 a --fields name that chooses nothing).
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

}  // namespace tiller::logtools
