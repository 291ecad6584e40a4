// The heartbeat channel of a node: TILLER_HEARTBEAT_ + its name upper-cased with '-' as '_'
// ("path-follower" -> TILLER_HEARTBEAT_PATH_FOLLOWER). Node uses it for its own heartbeat;
// tools that look for a process in a log (tiller-replay) use it to find that process's.
#pragma once

#include <string>

namespace tiller {

std::string heartbeat_channel_of(const std::string& node_name);

}  // namespace tiller
