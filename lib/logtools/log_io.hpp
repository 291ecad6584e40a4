// Reads an LCM log, plain or gzip-compressed (a name ending in .gz is decompressed with gzip
// into a temporary file first; the golden logs in test/data/golden are stored that way).
#pragma once

#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

std::vector<Event> read_any_log(const std::string& path, const std::string& channel_regex = ".*");

// The log's name without .gz and .lcmlog ("a/run.lcmlog.gz" -> "a/run").
std::string log_stem(const std::string& path);

}  // namespace tiller::logtools
