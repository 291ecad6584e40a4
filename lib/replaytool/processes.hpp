// The processes tiller-replay can rebuild from a config file (the registry of replayable nodes).
#pragma once

#include <vector>

#include "replaytool/compare.hpp"

namespace tiller::replaytool {
const std::vector<ProcessEntry>& replayable_processes();
}
