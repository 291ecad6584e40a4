// The cockpit's file glue (tiller-cockpit's main uses it; the node reads no file):
//   * the command token: read from its file, or made there at first start (32 random bytes from
//     libsodium as 64 hex digits, mode 0600, the folder made 0700 if missing); a group- or
//     world-readable file, or one holding fewer than 16 characters, is refused naming the file;
//   * a mission file's text uploaded from the page, parsed by the mission loader (lib/mission)
//     exactly as tiller-mission parses a file, errors naming the uploaded name, line and key.
#pragma once

#include <optional>
#include <string>

#include "mission/mission.hpp"

namespace tiller::cockpit {

// Throws std::runtime_error naming the file.
std::string load_or_create_token(const std::string& path);

// `name` is the uploaded file's name (.yaml, .yml, .csv or a QGroundControl .plan); lat/lon is
// converted to metres about `datum` (the vehicle's), else the plan's home. Throws config::Error
// or std::runtime_error whose message names it, the line (or item) and the key.
mission::Mission load_mission_text(const std::string& name, const std::string& text,
                                   const std::optional<mission::GeoPoint>& datum = {});

}  // namespace tiller::cockpit
