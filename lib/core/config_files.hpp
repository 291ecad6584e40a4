// Files named inside a config file (a vehicle file in a guidance or control config, ...).
#pragma once

#include <string>

namespace tiller::config {

// `rel` if absolute or not found; else the first of config_file's folder and its parents that
// holds it (so "config/vehicles/otter.yaml" in config/control/otter.yaml finds the source tree's).
std::string resolve_near(const std::string& rel, const std::string& config_file);

}  // namespace tiller::config
