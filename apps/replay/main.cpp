// tiller-replay: log replay regression. Feeds the recorded inputs of a process (or of every
// process that ran) through today's code at the recorded times and compares its outputs with
// the recorded ones: per channel "matching" or the first difference (time from the log's start,
// field, old, new), then a summary. Exit 0 when everything matches within the tolerance, 1 on a
// difference, 2 on a usage or manifest error. The plan is replaytool/plan.hpp.
//   tiller-replay LOG [--process NAME|all] [--config FILE] [--configs MANIFEST] [--tolerance X]
// MANIFEST (default: LOG's name with .replay.yaml, when it exists; tiller-launch writes one
// next to every log it starts, tools/rerecord-golden next to the golden logs):
//   root: /path/to/tiller   # relative configs resolve here (default: the current directory if
//                           # the file is there, else the source tree tiller-replay was built from)
//   live: true              # a live log (wall clock): ticks aligned to the recording
//   processes:              # what ran, with its config (a string) or its launch entry (a map)
//     mixer: config/mixer/otter.yaml
//     sim: {program: tiller-sim, config: config/sim/sim.yaml, args: [--vehicle, ...]}
//     done: {program: tiller-log, args: [wait, ...]}     # not replayable: reported as skipped
//   heartbeats: true        # compare heartbeats too (lockstep logs; not live ones)
//   tolerance: 0            # absolute, on every number field
//   time_tolerance_ms: 0
#include <iostream>
#include <limits>
#include <optional>

#include "logtools/log_io.hpp"
#include "replaytool/plan.hpp"
#include "replaytool/processes.hpp"
#include "runtime/app.hpp"

using namespace tiller;
using namespace tiller::replaytool;

namespace {
// A number option >= 0 (at most `hi`), or nothing when it was not given.
std::optional<double> optional_number(const app::Args& a, const std::string& name, double hi,
                                      const std::string& expected) {
  if (a.get(name).empty()) return std::nullopt;
  return app::number_option(a, name, 0, hi, expected);
}
}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-replay", [&]() -> int {
    app::Spec spec{
        "tiller-replay",
        "Replays a log through today's code and compares the outputs with the recorded ones\n"
        "(offline: it opens no LCM). Exit 0: all match within tolerance; 1: a difference; 2: "
        "usage or\nmanifest error.",
        "",
        {{"process", "NAME", "process to replay, or all (every replayable process that ran)",
          "all"},
         {"configs", "FILE",
          "manifest of each process's config (default: LOG.replay.yaml if present)", ""},
         {"tolerance", "X",
          "absolute tolerance on number fields, in their units, >= 0 (default: manifest's, else "
          "0)",
          ""},
         {"time-tolerance-ms", "MS",
          "tolerance on message times, ms >= 0 (default: manifest's, else 0; live logs 20)", ""},
         {"relative-tolerance", "F",
          "plus this fraction of |old value|, 0..1 (default: manifest's, else 0)", ""},
         {"live-match", "F",
          "live logs: fraction of each channel's messages that must match, 0..1 (default: "
          "manifest's, else 1)",
          ""},
         {"live", "", "a live log: align ticks to the recording (default: the manifest's live:)",
          ""},
         {"show", "N", "list the first N differences of each channel, a whole number >= 1", "1"},
         {"heartbeats", "", "compare heartbeats too (lockstep logs)", ""},
         {"list", "", "list the replayable processes and their default configs", ""}}};
    spec.takes_lcm_url = false;
    spec.config_help = "config of the one --process (instead of the manifest's or its default)";
    spec.arguments = "LOG";
    spec.max_positional = 1;
    const app::Args a = app::parse(argc, argv, spec);
    if (a.flag("list")) {
      for (const auto& e : replayable_processes())
        std::cout << e.name << "  (default config "
                  << (e.default_config.empty() ? "none: the vehicle's, from a manifest or --config"
                                               : e.default_config)
                  << ")\n";
      return 0;
    }
    if (a.positional.size() != 1) {
      std::cerr << "tiller-replay: give one log file (see --help)\n";
      return 2;
    }
    // Numeric options first, before anything is read or run.
    ReplayRequest req;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    req.relative_tolerance = optional_number(a, "relative-tolerance", 1, "a fraction from 0 to 1");
    req.live_match = optional_number(a, "live-match", 1, "a fraction from 0 to 1");
    req.tolerance = optional_number(a, "tolerance", kInf, "a number >= 0");
    req.time_tolerance_ms = optional_number(a, "time-tolerance-ms", kInf, "a number of ms >= 0");
    req.show = static_cast<std::size_t>(
        app::integer_option(a, "show", 1, INT64_MAX, "a whole number >= 1"));
    req.log_path = a.positional[0];
    req.process = a.get("process");
    req.manifest = a.get("configs");
    if (a.explicitly("config")) req.config = a.config;
    req.live = a.flag("live");
    req.heartbeats = a.flag("heartbeats");

    ReplayPlan plan = plan_from_manifest(req);
    const auto log = logtools::read_any_log(req.log_path);
    if (log.empty()) throw std::runtime_error(req.log_path + ": the log is empty");
    plan_from_log(plan, req, log);
    return run_plan(plan, log, req.show, std::cout) ? 0 : 1;
  });
}
