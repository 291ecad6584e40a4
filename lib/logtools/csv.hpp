// CSV export of logged messages, decoded field by field (lcm_schema.hpp). One row per message:
// t_s (seconds since `t0`), then the chosen fields. A field is chosen by its exact path
// ("position[1]") or by a prefix that ends at a '.' or '[' ("position" -> position[0..2],
// "waypoints" -> every waypoint field); no fields chosen = every field. Columns are the union
// over all messages (variable-length arrays), in first-seen order; a missing value is empty.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

bool field_selected(const std::string& path, const std::vector<std::string>& wanted);

// Returns the number of rows written; messages that do not decode are skipped and counted in
// *skipped when given.
std::size_t write_csv(std::ostream& os, const std::vector<Event>& events,
                      const std::string& channel, const std::vector<std::string>& fields, TimeUs t0,
                      std::size_t* skipped = nullptr);

}  // namespace tiller::logtools
