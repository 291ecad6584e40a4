#include "runtime/log.hpp"

#include "auth/trailer.hpp"

#include <lcm/lcm-cpp.hpp>

#include <stdexcept>

namespace tiller {

std::vector<Event> read_log(const std::string& path, const std::string& channel_regex) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error(path + ": cannot open LCM log");
  const std::regex re(channel_regex);
  std::vector<Event> out;
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    if (!std::regex_match(ev->channel, re)) continue;
    Event e;
    e.channel = ev->channel;
    e.time = ev->timestamp;
    // A signed message's trailer is not part of the message: logs read as the nodes saw them
    // (auth/trailer.hpp). Not verified here: a log is a record, not a command.
    const auto* p = static_cast<const std::uint8_t*>(ev->data);
    e.data.assign(p, p + auth::payload_size(p, ev->datalen));
    out.push_back(std::move(e));
  }
  return out;
}

LogWriter::LogWriter(const std::string& path) : file_(std::make_unique<lcm::LogFile>(path, "w")) {
  if (!file_->good()) throw std::runtime_error(path + ": cannot create LCM log");
}

LogWriter::~LogWriter() = default;

void LogWriter::write(const std::string& channel, const std::uint8_t* data, int size, TimeUs time) {
  lcm::LogEvent ev;
  ev.eventnum = 0;
  ev.timestamp = time;
  ev.channel = channel;
  ev.datalen = size;
  ev.data = const_cast<std::uint8_t*>(data);
  file_->writeEvent(&ev);
}

}  // namespace tiller
