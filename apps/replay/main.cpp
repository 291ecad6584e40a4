// tiller-replay: log replay regression. Feeds the recorded inputs of a process (or of every
// process that ran) through today's code at the recorded times and compares its outputs with
// the recorded ones: per channel "matching" or the first difference (time, field, old, new),
// then a summary. Exit 0 when everything matches within the tolerance, 1 otherwise.
//   tiller-replay LOG [--process NAME|all] [--config FILE] [--configs MANIFEST] [--tolerance X]
// MANIFEST (default: LOG's name with .replay.yaml, when it exists):
//   processes: {mixer: config/mixer/otter.yaml, ...}   # config of each process when recorded
//   heartbeats: true        # compare heartbeats too (lockstep logs; not live ones)
//   tolerance: 0            # absolute, on every number field
//   time_tolerance_ms: 0
#include <filesystem>
#include <iostream>
#include <map>

#include "core/config.hpp"
#include "logtools/log_io.hpp"
#include "processes.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/log.hpp"

using namespace tiller;
using namespace tiller::replaytool;

namespace {
std::string heartbeat_channel_of(const std::string& name) {
  std::string s = channels::kHeartbeatPrefix;
  for (char c : name)
    s += c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
bool explicit_option(int argc, char** argv, const std::string& name) {
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--" + name || s.rfind("--" + name + "=", 0) == 0) return true;
  }
  return false;
}
}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-replay", [&]() -> int {
    const app::Spec spec{
        "tiller-replay",
        "Replays a log through today's code and compares the outputs with the recorded ones.\n"
        "Usage: tiller-replay LOG [--process NAME|all] [--config FILE] [--configs MANIFEST]\n"
        "--config applies to the one --process. Exit 0: all match within tolerance; 1: a "
        "difference.",
        "",
        {{"process", "NAME", "process to replay, or all (every replayable process that ran)",
          "all"},
         {"configs", "FILE",
          "manifest of each process's config (default: LOG.replay.yaml if present)", ""},
         {"tolerance", "X", "absolute tolerance on number fields (default: manifest's, else 0)",
          ""},
         {"time-tolerance-ms", "MS", "tolerance on message times (default: manifest's, else 0)",
          ""},
         {"heartbeats", "", "compare heartbeats too (lockstep logs)", ""},
         {"list", "", "list the replayable processes and their default configs", ""}}};
    const app::Args a = app::parse(argc, argv, spec);
    const auto& entries = replayable_processes();
    if (a.flag("list")) {
      for (const auto& e : entries)
        std::cout << e.name << "  (default config " << e.default_config << ")\n";
      return 0;
    }
    if (a.positional.size() != 1) {
      std::cerr << "tiller-replay: give one log file (see --help)\n";
      return 2;
    }
    const std::string log_path = a.positional[0];
    std::map<std::string, std::string> configs;
    Tolerance tol;
    bool heartbeats = a.flag("heartbeats");
    std::string manifest = a.get("configs");
    if (manifest.empty()) {
      const auto candidate = logtools::log_stem(log_path) + ".replay.yaml";
      if (std::filesystem::exists(candidate)) manifest = candidate;
    }
    if (!manifest.empty()) {
      const auto m = config::Value::load_file(manifest);
      if (auto ps = m.find("processes")) {
        for (const auto& k : ps->keys()) configs[k] = ps->string(k);
      }
      heartbeats = heartbeats || m.boolean_or("heartbeats", false);
      tol.abs = m.number_or("tolerance", 0.0, config::Range::at_least(0.0));
      tol.time_us =
          from_seconds(m.number_or("time_tolerance_ms", 0.0, config::Range::at_least(0.0)) * 1e-3);
      m.check_all_used();
    }
    if (!a.get("tolerance").empty()) tol.abs = std::stod(a.get("tolerance"));
    if (!a.get("time-tolerance-ms").empty())
      tol.time_us = from_seconds(std::stod(a.get("time-tolerance-ms")) * 1e-3);

    const auto log = logtools::read_any_log(log_path);
    if (log.empty()) throw std::runtime_error(log_path + ": the log is empty");
    std::vector<const ProcessEntry*> chosen;
    const std::string which = a.get("process");
    for (const auto& e : entries) {
      if (which == "all" && !configs.empty() && !configs.count(e.name)) {
        continue;  // a manifest names the processes to replay
      } else if (which == "all") {
        const std::string hb = heartbeat_channel_of(e.name);
        bool ran = false;
        for (const auto& ev : log) {
          if (ev.channel == hb) {
            ran = true;
            break;
          }
        }
        if (ran) chosen.push_back(&e);
      } else if (e.name == which) {
        chosen.push_back(&e);
      }
    }
    if (chosen.empty()) {
      std::cerr << "tiller-replay: "
                << (which == "all" ? "no replayable process ran in " + log_path
                                   : "no replayable process named " + which)
                << " (see --list)\n";
      return 2;
    }
    if (explicit_option(argc, argv, "config")) {
      if (which == "all") {
        std::cerr << "tiller-replay: --config needs --process NAME\n";
        return 2;
      }
      configs[which] = a.config;
    }
    bool ok = true;
    for (const ProcessEntry* e : chosen) {
      const std::string cfg = configs.count(e->name) ? configs[e->name] : e->default_config;
      const auto rep = replay_process(*e, cfg, log, tol, heartbeats);
      std::cout << format_report(rep);
      ok = ok && rep.ok();
    }
    std::cout << "tiller-replay: " << (ok ? "PASS" : "FAIL") << " (" << chosen.size() << " process"
              << (chosen.size() > 1 ? "es" : "") << ", tolerance " << tol.abs << ", time tolerance "
              << to_seconds(tol.time_us) * 1e3 << " ms)\n";
    return ok ? 0 : 1;
  });
}
