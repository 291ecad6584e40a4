// Log replay regression: runs one process's node on the inputs recorded in a log (the
// foundation's ReplayExecutor, recorded times) and compares what it publishes today with what
// it published when the log was recorded, channel by channel and field by field (fields
// decoded from the .lcm definitions, logtools/lcm_schema.hpp). Without a time tolerance the
// i-th recorded message of a channel is compared with the i-th replayed one (lockstep logs,
// bit for bit); with one (live logs), each recorded message with the replayed one nearest in
// time. Then every field: numbers within an absolute tolerance (*utime fields within the time
// tolerance), text exactly. Times in us.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "runtime/event.hpp"
#include "runtime/node.hpp"

namespace tiller::replaytool {

struct Tolerance {
  double abs = 0.0;    // |old - new| allowed for any number field
  TimeUs time_us = 0;  // allowed difference of message times
};

struct Difference {
  TimeUs time = 0;        // recorded time of the message (us)
  std::size_t index = 0;  // message index in the channel
  std::string field;      // "time", "count" or a field path
  std::string old_value, new_value;
};

struct ChannelReport {
  std::string channel;
  std::size_t recorded = 0, replayed = 0;
  std::size_t matching = 0;   // messages equal within tolerance
  std::size_t differing = 0;  // messages with at least one field beyond tolerance
  double max_abs_diff = 0.0;  // over all number fields (also those within tolerance)
  std::string max_abs_field;
  std::optional<Difference> first;
  bool by_time = false;  // matched by nearest time (time tolerance > 0): counts may differ
  bool ok() const { return (by_time || recorded == replayed) && differing == 0; }
};

ChannelReport compare_channel(const std::string& channel, const std::vector<Event>& recorded,
                              const std::vector<Event>& replayed, const Tolerance& tol);

// One process Tiller can replay: how to build its node from a config file, and which channels
// it publishes (besides its heartbeat).
struct ProcessEntry {
  std::string name;            // node name, e.g. "mixer"
  std::string default_config;  // relative to the source tree
  std::vector<std::string> outputs;
  std::function<std::unique_ptr<Node>(const std::string& config_path)> make;
};

struct ProcessReport {
  std::string process;
  std::string config;
  std::size_t inputs = 0;  // recorded messages fed
  std::vector<ChannelReport> channels;
  bool ok() const;
};

// Replays `log` (all channels, sorted by time) through a fresh node of `entry`; compares on
// entry.outputs, the node's heartbeat and any other channel it publishes today. Heartbeats are
// compared only when `heartbeats` is true (a live log's heartbeat times are the wall clock's).
ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol, bool heartbeats);

// Human-readable report: per channel "matching" or the first difference, then a summary line.
std::string format_report(const ProcessReport& r);

}  // namespace tiller::replaytool
