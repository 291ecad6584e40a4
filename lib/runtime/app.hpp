// The common command line of every tiller-<name> program: --help, --config FILE,
// --lcm-url URL, plus program-specific options. Keeps each main() a few lines long.
//
// Paths: a relative --config (given or default) that does not exist from the current directory
// is looked up in the source tree (<source>/ then <source>/config/), so every program finds its
// default config from any directory; so are the defaults of options whose value is a FILE.
// Standard options a program does not use (Spec::takes_config / takes_lcm_url false) are not
// listed by --help and are refused with a message (exit 2) instead of being silently ignored;
// so is a positional argument the program does not take (Spec::arguments, max_positional,
// commands).
//
// --help prints one usage line ("Usage: tiller-plot [options] LOG"), the summary, then each
// option once with its value, unit or range in the help text and its default (when it has a
// fixed one) shown once, from Option::default_value.
//
// Message signing (docs/safety.md, "Who may command"): a program that opens LCM also takes
//   --key-file FILE      the vehicle's key (default: $TILLER_KEY_FILE), checked at start-up: a
//                        missing, malformed or group/world-readable file is exit 2 naming it
//   --require-signed     refuse unsigned input (default: $TILLER_REQUIRE_SIGNED = 1/true/0/false)
//   --auth-window-s S    replay window (default: $TILLER_AUTH_WINDOW_S, else 1)
// and, for every message's own utime (docs/safety.md, "Stalls and liveness"),
//   --clock-offset-s S   bound on the offset between this computer's clock and its senders'
//                        (default: $TILLER_CLOCK_OFFSET_S, else 0.25; [0, 10])
// tiller-launch sets the four variables from the launch file for every process.
//
// Real time (runtime/realtime.hpp, docs/operations.md "Real time"): such a program also takes
//   --realtime-priority N   SCHED_FIFO priority 1..99
//   --lock-memory           mlockall(MCL_CURRENT | MCL_FUTURE)
//   --realtime-required     not permitted -> exit 2 (else a warning per refusal, and it runs)
// applied by parse() itself, before the program opens anything; tiller-launch passes them
// from a process's `realtime:` entry.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "auth/verifier.hpp"

namespace tiller::app {

struct Option {
  std::string name;        // long name without dashes, e.g. "vehicle"
  std::string value_name;  // e.g. "FILE"; empty for a flag
  std::string help;
  std::string default_value;
};

struct Spec {
  std::string program;         // e.g. "tiller-mixer"
  std::string summary;         // one line: what it does
  std::string default_config;  // relative to the current directory or the source tree; may be empty
  std::vector<Option> options;
  bool takes_config = true;   // false: --config is refused (the program has no config file)
  bool takes_lcm_url = true;  // false: --lcm-url is refused (the program opens no LCM)
  // false: --realtime-priority, --lock-memory, --realtime-required are refused (also when
  // takes_lcm_url is false). tiller-launch: its children would inherit SCHED_FIFO.
  bool takes_realtime = true;
  // Positional arguments, as the usage line shows them after "[options]" ("LOG"); empty: none.
  std::string arguments = {};
  // At most this many positional arguments; the first one more is refused, naming it.
  std::size_t max_positional = 0;
  // Commands (tiller-log summary LOG): when the first positional argument is one of these, at
  // most commands[it] more follow; a first word that is neither a command nor allowed by
  // max_positional is refused, naming it and the commands.
  std::map<std::string, std::size_t> commands = {};
  std::string config_help = "YAML config";  // --config's line in --help
};

struct Args {
  std::string config;                         // path to the YAML config
  std::string lcm_url;                        // LCM URL (TTL 0 unless given)
  std::map<std::string, std::string> values;  // program-specific options (flags: "1")
  std::vector<std::string> positional;
  std::set<std::string> given;  // options named on the command line ("config", "lcm-url", ...)
  auth::Policy auth;            // signing: key loaded and checked, require_signed, window
  const std::string& get(const std::string& name) const;
  bool flag(const std::string& name) const;
  // True when --NAME was on the command line (not just its default).
  bool explicitly(const std::string& name) const { return given.count(name) > 0; }
};

// Parses argv; prints the help and exits 0 on --help; exits 2 with a message naming the problem
// and the usage line on bad usage (an unknown option, a missing value, an option or a
// positional argument the program does not take).
Args parse(int argc, char** argv, const Spec& spec);

// `path` as given if it is empty, absolute or exists from the current directory; else the
// first of <source>/path and <source>/config/path that exists; else `path` unchanged.
std::string resolve_path(const std::string& path);

// A numeric option's value, checked whole before anything starts: the full string must be a
// finite number in [lo, hi] (integer_option: a whole number in [lo, hi]). Otherwise throws
// std::runtime_error "--NAME: expected EXPECTED, got 'VALUE'", which guarded_main prints and
// turns into exit status 2.
double number_option(const Args& a, const std::string& name, double lo, double hi,
                     const std::string& expected);
std::int64_t integer_option(const Args& a, const std::string& name, std::int64_t lo,
                            std::int64_t hi, const std::string& expected);

// "a,b,,c" -> {"a", "b", "c"} (empty items dropped): list-valued options such as --group A,B.
std::vector<std::string> split_list(const std::string& s);

// Runs body(); a config or start-up error is printed as "<program>: <message>" and gives 2.
int guarded_main(const std::string& program, const std::function<int()>& body);

}  // namespace tiller::app
