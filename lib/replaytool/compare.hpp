// Log replay regression: runs one process's node on the inputs recorded in a log (the
// foundation's ReplayExecutor for lockstep logs; for live logs a loop that runs each tick where
// the recording shows the live process ran it) and compares what it publishes today with what
// it published when the log was recorded, channel by channel and field by field (fields
// decoded from the .lcm definitions, logtools/lcm_schema.hpp). Without a time tolerance the
// i-th recorded message of a channel is compared with the i-th replayed one (lockstep logs,
// bit for bit); with one (live logs), messages are matched in order, each recorded one with the
// next replayed one within the time tolerance (missing and extra ones counted), and a channel
// passes when Tolerance::live_match of its messages match. Then every field: numbers within
// abs + rel x |old| (*utime fields within the time tolerance), text exactly. Times in us.
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
  double rel = 0.0;    // plus this fraction of |old| (number fields)
  // Live logs: the fraction of a channel's messages that must match (each within the tolerances
  // above); the rest are the ticks that saw an input in another order than live. 1: all.
  double live_match = 1.0;
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
  std::vector<Difference> shown;  // the first `show` differences (compare_channel's argument)
  bool by_time = false;           // matched by nearest time (time tolerance > 0): counts may differ
  // By time: replayed messages that are no recorded message's nearest match (extra outputs).
  std::size_t unmatched_replayed = 0;
  // By time: per number field (times excluded) rms(new - old) / rms(old) over matched pairs;
  // the worst field. A live replay's verdict uses it (ReplayOptions::live).
  double worst_rel_rms = 0.0;
  std::string worst_rel_field;
  double live_match = 1.0;  // from the Tolerance (by time)
  bool ok() const {
    if (!by_time) return recorded == replayed && differing == 0;
    const double allowed = (1.0 - live_match) * static_cast<double>(recorded) + 1e-9;
    return static_cast<double>(differing) <= allowed &&
           static_cast<double>(unmatched_replayed) <= allowed;
  }
};

ChannelReport compare_channel(const std::string& channel, const std::vector<Event>& recorded,
                              const std::vector<Event>& replayed, const Tolerance& tol,
                              std::size_t show = 1);

// One process Tiller can replay: how to build its node from a config file, and which channels
// it publishes (besides its heartbeat).
struct ProcessEntry {
  std::string name;            // node name, e.g. "mixer"
  std::string default_config;  // relative to the source tree
  // Compared when the node made from the config advertises them (tiller-sim --odometry estimated
  // does not advertise TILLER_ODOMETRY: in that log it is tiller-nav's), and whatever it publishes.
  std::vector<std::string> outputs;
  std::function<std::unique_ptr<Node>(const std::string& config_path)> make;
  // When set, used instead of `make` with the process's recorded command-line arguments (from
  // a launch manifest), for options that override the config (tiller-sim --vehicle).
  std::function<std::unique_ptr<Node>(const std::string& config_path,
                                      const std::vector<std::string>& args)>
      make_with_args = {};
  // Its outputs integrate its inputs (controller integrators, vehicle dynamics): replaying a
  // live log, one input taken in another order than live changes every later output, so the
  // comparison is shown but not part of the verdict (lockstep logs, the golden ones, decide).
  bool integrating = false;
  // When set, given the log before the replay: for what a process drew at its start and
  // announced (tiller-esc's boot nonce, taken from its first recorded TILLER_ARM_STATE).
  std::function<void(Node& node, const std::vector<Event>& log)> prime = {};
};

struct ReplayOptions {
  bool heartbeats = false;  // compare heartbeats (lockstep logs; a live log's are wall-clock)
  // A live log (processes on the wall clock, recorded by lcm-logger): ticks run where the
  // recording shows the live process ran them (its outputs stamped utime = the tick's grid
  // time), inputs are fed from the process's first output to its last (no warm-up before it
  // started, no ticks after it stopped), and the node's shutdown() runs at its last output.
  bool live = false;
  std::vector<std::string> args;  // recorded command-line arguments (make_with_args)
  std::size_t show = 1;           // differences listed per channel
};

struct ProcessReport {
  std::string process;
  std::string config;
  std::size_t inputs = 0;  // recorded messages fed
  std::vector<ChannelReport> channels;
  TimeUs origin = 0;  // the log's first event (differences are printed relative to it)
  bool live = false;
  TimeUs live_from = 0, live_to = 0;         // live: the span replayed (the process's outputs)
  std::size_t aligned_ticks = 0, ticks = 0;  // live: ticks placed where the recording ran them
  bool informational = false;  // live replay of an integrating process: not in the verdict
  bool ok() const;
};

// Replays `log` (all channels, sorted by time) through a fresh node of `entry`; compares on
// entry.outputs, the node's heartbeat and any other channel it publishes today. Heartbeats are
// compared only when `heartbeats` is true (a live log's heartbeat times are the wall clock's).
ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol, bool heartbeats);
ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol,
                             const ReplayOptions& opt);

// Human-readable report: per channel "matching" or the first difference, then a summary line.
std::string format_report(const ProcessReport& r);

}  // namespace tiller::replaytool
