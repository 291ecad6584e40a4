// The launch file's message-signing settings (key_file, require_signed, auth_window_s,
// create_key) and clock_offset_s turned into what every child process gets: TILLER_KEY_FILE
// (absolute), TILLER_REQUIRE_SIGNED (1 or 0), TILLER_AUTH_WINDOW_S and TILLER_CLOCK_OFFSET_S,
// which runtime/app.hpp reads as the defaults of --key-file / --require-signed /
// --auth-window-s / --clock-offset-s. See docs/safety.md.
#pragma once

#include <map>
#include <ostream>
#include <string>

#include "launch/launch_file.hpp"

namespace tiller::launch {

// `key_file_override` (tiller-launch --key-file) replaces the file's key_file when not empty.
// The key file is checked here, before any process starts: a missing (unless create_key, which
// makes it with mode 0600 and says so on `out`), malformed or group/world-readable key throws
// std::runtime_error "LAUNCH_FILE:LINE: key_file: key file 'PATH': why".
std::map<std::string, std::string> signing_env(const LaunchFile& lf,
                                               const std::map<std::string, std::string>& vars,
                                               const std::string& key_file_override,
                                               std::ostream& out);

// One line for the launcher's output: "signing: key FILE, unsigned input refused" (or
// "..., accepted"), or "signing: off (no key_file)", from signing_env's result.
std::string signing_summary(const LaunchFile& lf, const std::map<std::string, std::string>& env);

}  // namespace tiller::launch
