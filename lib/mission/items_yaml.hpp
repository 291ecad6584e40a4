// Our YAML mission's items, home, fence and rally points (format: items_yaml.cpp's header
// comment and docs/missions.md) into the mission model. Errors are config::Error (file, line, key).
#pragma once

#include "core/config.hpp"
#include "mission/mission.hpp"

namespace tiller::mission {

void load_items(const config::Value& root, Mission& m);

}  // namespace tiller::mission
