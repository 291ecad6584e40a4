// LCM event logs (the lcm-logger format) read and written with lcm::LogFile.
// Event timestamps are the recorded receive times, in us.
#pragma once

#include <memory>
#include <regex>
#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace lcm {
class LogFile;
}

namespace tiller {

// Reads every event of a log (optionally only channels matching `channel_regex`, anchored).
// Signed messages come back without their trailer (auth/trailer.hpp), as nodes receive them.
// Throws std::runtime_error naming the file if it cannot be opened.
std::vector<Event> read_log(const std::string& path, const std::string& channel_regex = ".*");

// Appends events to a new log file.
class LogWriter {
 public:
  explicit LogWriter(const std::string& path);  // throws std::runtime_error if it cannot open
  ~LogWriter();
  void write(const std::string& channel, const std::uint8_t* data, int size, TimeUs time);
  void write(const Event& e) {
    write(e.channel, e.data.data(), static_cast<int>(e.data.size()), e.time);
  }

 private:
  std::unique_ptr<lcm::LogFile> file_;
};

}  // namespace tiller
