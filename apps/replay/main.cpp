// tiller-replay: log replay regression. Feeds the recorded inputs of a process (or of every
// process that ran) through today's code at the recorded times and compares its outputs with
// the recorded ones: per channel "matching" or the first difference (time from the log's start,
// field, old, new), then a summary. Exit 0 when everything matches within the tolerance, 1 on a
// difference, 2 on a usage or manifest error.
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
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <set>

#include "core/config.hpp"
#include "logtools/log_io.hpp"
#include "processes.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/log.hpp"

using namespace tiller;
using namespace tiller::replaytool;
namespace fs = std::filesystem;

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

struct Planned {
  const ProcessEntry* entry = nullptr;
  std::string config;  // as given (manifest, --config or the default)
  std::vector<std::string> args;
};

}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-replay", [&]() -> int {
    const app::Spec spec{
        "tiller-replay",
        "Replays a log through today's code and compares the outputs with the recorded ones.\n"
        "Usage: tiller-replay LOG [--process NAME|all] [--config FILE] [--configs MANIFEST]\n"
        "--config applies to the one --process. Exit 0: all match within tolerance; 1: a "
        "difference; 2: usage or manifest error.",
        "",
        {{"process", "NAME", "process to replay, or all (every replayable process that ran)",
          "all"},
         {"configs", "FILE",
          "manifest of each process's config (default: LOG.replay.yaml if present)", ""},
         {"tolerance", "X",
          "absolute tolerance on number fields, >= 0 (default: manifest's, else 0)", ""},
         {"time-tolerance-ms", "MS",
          "tolerance on message times, >= 0 (default: manifest's, else 0)", ""},
         {"relative-tolerance", "F",
          "plus this fraction of |old value|, 0..1 (default: manifest's, else 0)", ""},
         {"live-match", "F",
          "live logs: fraction of each channel's messages that must match, 0..1 (default: "
          "manifest's, else 1)",
          ""},
         {"live", "", "a live log: align ticks to the recording (default: the manifest's live:)",
          ""},
         {"show", "N", "list the first N differences of each channel (default 1)", "1"},
         {"heartbeats", "", "compare heartbeats too (lockstep logs)", ""},
         {"list", "", "list the replayable processes and their default configs", ""}}};
    const app::Args a = app::parse(argc, argv, spec);
    const auto& entries = replayable_processes();
    auto entry_named = [&](const std::string& n) -> const ProcessEntry* {
      for (const auto& e : entries)
        if (e.name == n) return &e;
      return nullptr;
    };
    std::string names;
    for (const auto& e : entries) names += (names.empty() ? "" : ", ") + e.name;
    if (a.flag("list")) {
      for (const auto& e : entries)
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
    std::optional<double> opt_tol, opt_time_tol, opt_rel, opt_match;
    if (!a.get("relative-tolerance").empty())
      opt_rel = app::number_option(a, "relative-tolerance", 0, 1, "a fraction from 0 to 1");
    if (!a.get("live-match").empty())
      opt_match = app::number_option(a, "live-match", 0, 1, "a fraction from 0 to 1");
    if (!a.get("tolerance").empty())
      opt_tol = app::number_option(a, "tolerance", 0, std::numeric_limits<double>::infinity(),
                                   "a number >= 0");
    if (!a.get("time-tolerance-ms").empty())
      opt_time_tol =
          app::number_option(a, "time-tolerance-ms", 0, std::numeric_limits<double>::infinity(),
                             "a number of ms >= 0");
    const std::int64_t show_n = app::integer_option(a, "show", 1, INT64_MAX, "a whole number >= 1");
    const std::string which = a.get("process");
    if (which != "all" && !entry_named(which)) {
      std::cerr << "tiller-replay: --process: no replayable process named \"" << which
                << "\" (replayable: " << names << ", or all)\n";
      return 2;
    }

    const std::string log_path = a.positional[0];
    Tolerance tol;
    bool heartbeats = a.flag("heartbeats");
    bool live = a.flag("live");
    std::string manifest = a.get("configs");
    if (manifest.empty()) {
      const auto candidate = logtools::log_stem(log_path) + ".replay.yaml";
      if (fs::exists(candidate)) manifest = candidate;
    }
    // Where relative config paths resolve: the manifest's root, else the current directory when
    // the file is there, else the source tree.
    std::string root;
    auto resolve = [&](const std::string& p) -> std::string {
      if (p.empty() || fs::path(p).is_absolute()) return p;
      if (!root.empty()) return (fs::path(root) / p).string();
      if (fs::exists(p)) return p;
      const std::string in_src = std::string(TILLER_SOURCE_DIR) + "/" + p;
      return fs::exists(in_src) ? in_src : p;
    };
    std::vector<Planned> plan;
    std::vector<std::string> skipped;  // "name (why)"
    bool from_manifest = false;
    if (!manifest.empty()) {
      const auto m = config::Value::load_file(manifest);
      if (auto r = m.find("root")) {
        root = r->as_string();
        if (!fs::is_directory(root)) r->fail("an existing directory (the tree the log ran in)");
      }
      live = live || m.boolean_or("live", false);
      heartbeats = heartbeats || m.boolean_or("heartbeats", false);
      tol.abs = m.number_or("tolerance", 0.0, config::Range::at_least(0.0));
      tol.rel = m.number_or("relative_tolerance", 0.0, {0.0, 1.0});
      tol.live_match = m.number_or("live_match", 1.0, {0.0, 1.0});
      tol.time_us =
          from_seconds(m.number_or("time_tolerance_ms", 0.0, config::Range::at_least(0.0)) * 1e-3);
      for (const char* info : {"launch_file", "log", "written_by"})
        if (auto v = m.find(info)) v->mark_used();
      if (auto ps = m.find("processes")) {
        if (!ps->is_map()) ps->fail("a map of process name: config (or {program, config, args})");
        from_manifest = true;
        for (const auto& k : ps->keys()) {
          const auto v = ps->at(k);
          Planned p;
          std::string program;
          if (v.is_map()) {
            program = v.string_or("program", "");
            p.config = v.string_or("config", "");
            if (auto ar = v.find("args")) {
              if (!ar->is_sequence()) ar->fail("a sequence of strings");
              for (const auto& s : ar->items()) p.args.push_back(s.as_string());
            }
          } else {
            p.config = v.as_string();
          }
          // Launch entries name the program (tiller-mixer is the mixer whatever the process is
          // called); plain entries must name a replayable process.
          const std::string base = fs::path(program).filename().string();
          p.entry = base.rfind("tiller-", 0) == 0 ? entry_named(base.substr(7)) : nullptr;
          if (!p.entry) p.entry = entry_named(k);
          if (!p.entry && !v.is_map())
            v.fail("a process tiller-replay knows (" + names + "), not \"" + k + "\"");
          if (!p.entry) {
            skipped.push_back(k + " (" + (program.empty() ? "no program" : base) +
                              ": not a replayable process)");
            continue;
          }
          if (which != "all" && p.entry->name != which) continue;
          if (p.config.empty()) p.config = p.entry->default_config;
          plan.push_back(p);
        }
      }
      m.check_all_used();
    }
    if (opt_tol) tol.abs = *opt_tol;
    if (opt_rel) tol.rel = *opt_rel;
    if (opt_match) tol.live_match = *opt_match;
    if (opt_time_tol) tol.time_us = from_seconds(*opt_time_tol * 1e-3);
    if (live && tol.time_us == 0) tol.time_us = 20'000;  // a live log's times are the wall clock's

    const auto log = logtools::read_any_log(log_path);
    if (log.empty()) throw std::runtime_error(log_path + ": the log is empty");
    if (!from_manifest) {
      for (const auto& e : entries) {
        if (which != "all" && e.name != which) continue;
        if (which == "all") {
          const std::string hb = heartbeat_channel_of(e.name);
          bool ran = false;
          for (const auto& ev : log) {
            if (ev.channel == hb) {
              ran = true;
              break;
            }
          }
          if (!ran) continue;
        }
        plan.push_back(Planned{&e, e.default_config, {}});
      }
      // Processes that ran (their heartbeat is in the log) but cannot be replayed: say so.
      if (which == "all") {
        std::set<std::string> hbs;
        for (const auto& ev : log)
          if (ev.channel.rfind(channels::kHeartbeatPrefix, 0) == 0) hbs.insert(ev.channel);
        for (const auto& hb : hbs) {
          bool known = false;
          for (const auto& e : entries) known = known || heartbeat_channel_of(e.name) == hb;
          if (known) continue;
          std::string name = hb.substr(std::string(channels::kHeartbeatPrefix).size());
          for (char& c : name)
            c = c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
          skipped.push_back(name + " (its heartbeat is in the log: not a replayable process)");
        }
      }
    }
    if (explicit_option(argc, argv, "config")) {
      if (which == "all") {
        std::cerr << "tiller-replay: --config needs --process NAME\n";
        return 2;
      }
      if (plan.empty()) plan.push_back(Planned{entry_named(which), "", {}});
      for (auto& p : plan) p.config = a.config;
    }
    // Processes whose config is the vehicle's have no default.
    for (auto it = plan.begin(); it != plan.end();) {
      if (!it->config.empty()) {
        ++it;
        continue;
      }
      if (which != "all") {
        std::cerr << "tiller-replay: " << it->entry->name
                  << " has no default config (it is the vehicle's): give --config FILE or a "
                     "manifest (--configs)\n";
        return 2;
      }
      skipped.push_back(it->entry->name + " (needs its vehicle's config: a manifest or --process " +
                        it->entry->name + " --config FILE)");
      it = plan.erase(it);
    }
    for (const auto& s : skipped) std::cout << "skipped: " << s << "\n";
    if (plan.empty()) {
      std::cerr << "tiller-replay: "
                << (which == "all" ? "no replayable process ran in " + log_path +
                                         (from_manifest ? " (manifest " + manifest + ")" : "")
                                   : which + " is not among the processes of " + manifest)
                << " (see --list)\n";
      return 2;
    }
    bool ok = true;
    // The verdict names what it covers: on a live log the integrating processes are replayed
    // and reported but are not in it (see format_report).
    std::vector<std::string> checked, informational;
    for (const Planned& p : plan) {
      ReplayOptions o;
      o.heartbeats = heartbeats && !live;
      o.live = live;
      o.show = static_cast<std::size_t>(show_n);
      for (const auto& s : p.args) {
        // Recorded paths are relative to the tree the run was started in.
        const auto eq = s.find('=');
        const std::string v = eq == std::string::npos ? s : s.substr(eq + 1);
        const bool path_like = !v.empty() && v[0] != '-' && v.find('/') != std::string::npos;
        const std::string r = path_like ? resolve(v) : v;
        o.args.push_back(eq == std::string::npos ? r : s.substr(0, eq + 1) + r);
      }
      const auto rep = replay_process(*p.entry, resolve(p.config), log, tol, o);
      std::cout << format_report(rep);
      ok = ok && rep.ok();
      (rep.informational ? informational : checked).push_back(p.entry->name);
    }
    const auto listed = [](const std::vector<std::string>& ns) {
      std::string s;
      for (const auto& n : ns) s += (s.empty() ? "" : ", ") + n;
      return s;
    };
    std::cout << "tiller-replay: " << (ok ? "PASS" : "FAIL") << " (" << checked.size()
              << (checked.size() == 1 ? " process" : " processes") << " checked"
              << (checked.empty() ? "" : ": " + listed(checked))
              << (informational.empty() ? ""
                                        : "; " + std::to_string(informational.size()) +
                                              " informational: " + listed(informational))
              << (live ? "; live log: ticks aligned to the recording" : "") << "; tolerance "
              << tol.abs << (tol.rel > 0 ? " + " + std::to_string(tol.rel) + " x |old|" : "")
              << (live && tol.live_match < 1
                      ? ", " + std::to_string(static_cast<int>(std::lround(tol.live_match * 100))) +
                            "% of messages"
                      : "")
              << ", time tolerance " << to_seconds(tol.time_us) * 1e3 << " ms"
              << (skipped.empty() ? "" : ", " + std::to_string(skipped.size()) + " skipped")
              << ")\n";
    return ok ? 0 : 1;
  });
}
