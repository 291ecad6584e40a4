// A summary of an LCM log: per channel its type, message count, rate, largest gap and number of
// gaps, and per process its last heartbeat (state, status, received/rejected/stale/published and
// every non-zero named counter such as "rejected.odometry.nan"), its worst state and its missed
// ticks; then what needs attention: a process that missed more than 1 % of its ticks, was ever
// DEGRADED or FAULT, dropped or rejected messages, or a channel with messages that do not
// decode. format_summary prints it with a legend of the columns. Times in us, rates in Hz.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "runtime/event.hpp"

namespace tiller::logtools {

struct ChannelStats {
  std::string channel;
  std::string type;  // "?" when the fingerprint is not a Tiller type
  std::int64_t count = 0;
  std::int64_t bytes = 0;
  std::int64_t undecodable = 0;
  TimeUs first = 0, last = 0;
  double rate_hz = 0.0;  // (count - 1) / (last - first)
  TimeUs median_period = 0;
  TimeUs max_gap = 0;     // largest interval between two messages
  TimeUs max_gap_at = 0;  // time the largest gap began
  std::int64_t gaps = 0;  // intervals longer than max(3 x median period, 0.2 s)
};

struct ProcessHealth {
  std::string process;
  std::int64_t heartbeats = 0;
  TimeUs last_seen = 0;
  int state = 0;  // heartbeat_t STATE_*
  std::string status;
  std::int64_t received = 0, rejected = 0, stale = 0, published = 0;
  std::map<std::string, std::int64_t> counters;  // non-zero named counters of the last heartbeat
  // The worst state of any heartbeat (OK < DEGRADED < FAULT), when it was first seen and why.
  int worst_state = 0;
  TimeUs worst_at = 0;
  std::string worst_status;
  // From the last heartbeat's "ticks.run" and "ticks.missed" (the live executor counts both;
  // ticks_run is -1 when the log has no "ticks.run", as in logs from before it was counted).
  std::int64_t ticks_run = -1, ticks_missed = 0;
  // ticks_missed / (ticks_run + ticks_missed); -1 when ticks_run is unknown.
  double missed_fraction() const;
};

// Above this fraction of missed ticks a process needs attention.
inline constexpr double kMissedTicksLimit = 0.01;

struct LogSummary {
  TimeUs start = 0, end = 0;
  std::int64_t events = 0;
  std::vector<ChannelStats> channels;    // by channel name
  std::vector<ProcessHealth> processes;  // by process name
  std::vector<std::string> attention;    // one line each: "esc: missed 1026 of 8550 ticks ..."
};

LogSummary summarize(const std::vector<Event>& events);
std::string format_summary(const LogSummary& s);

}  // namespace tiller::logtools
