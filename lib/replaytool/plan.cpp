#include "replaytool/plan.hpp"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <set>
#include <stdexcept>

#include "core/config.hpp"
#include "logtools/log_io.hpp"
#include "replaytool/processes.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/heartbeat_name.hpp"

namespace tiller::replaytool {

namespace fs = std::filesystem;

const ProcessEntry* replayable(const std::string& name) {
  for (const auto& e : replayable_processes())
    if (e.name == name) return &e;
  return nullptr;
}

std::string replayable_names() {
  std::string names;
  for (const auto& e : replayable_processes()) names += (names.empty() ? "" : ", ") + e.name;
  return names;
}

std::string ReplayPlan::resolve(const std::string& p) const {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  if (!root.empty()) return (fs::path(root) / p).string();
  return app::resolve_path(p);
}

namespace {
// One entry of the manifest's processes: a config path, or a launch entry {program, config, args}.
void plan_manifest_process(ReplayPlan& plan, const ReplayRequest& req, const std::string& k,
                           const config::Value& v) {
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
  p.entry = base.rfind("tiller-", 0) == 0 ? replayable(base.substr(7)) : nullptr;
  if (!p.entry) p.entry = replayable(k);
  if (!p.entry && !v.is_map())
    v.fail("a process tiller-replay knows (" + replayable_names() + "), not \"" + k + "\"");
  if (!p.entry) {
    plan.skipped.push_back(k + " (" + (program.empty() ? "no program" : base) +
                           ": not a replayable process)");
    return;
  }
  if (req.process != "all" && p.entry->name != req.process) return;
  if (p.config.empty()) p.config = p.entry->default_config;
  plan.processes.push_back(p);
}
}  // namespace

ReplayPlan plan_from_manifest(const ReplayRequest& req) {
  if (req.process != "all" && !replayable(req.process))
    throw std::runtime_error("--process: no replayable process named \"" + req.process +
                             "\" (replayable: " + replayable_names() + ", or all)");
  ReplayPlan plan;
  plan.process = req.process;
  plan.log_path = req.log_path;
  plan.live = req.live;
  plan.heartbeats = req.heartbeats;
  plan.manifest = req.manifest;
  if (plan.manifest.empty()) {
    const auto candidate = logtools::log_stem(req.log_path) + ".replay.yaml";
    if (fs::exists(candidate)) plan.manifest = candidate;
  }
  Tolerance& tol = plan.tol;
  if (!plan.manifest.empty()) {
    const auto m = config::Value::load_file(plan.manifest);
    if (auto r = m.find("root")) {
      plan.root = r->as_string();
      if (!fs::is_directory(plan.root)) r->fail("an existing directory (the tree the log ran in)");
    }
    plan.live = plan.live || m.boolean_or("live", false);
    plan.heartbeats = plan.heartbeats || m.boolean_or("heartbeats", false);
    tol.abs = m.number_or("tolerance", 0.0, config::Range::at_least(0.0));
    tol.rel = m.number_or("relative_tolerance", 0.0, {0.0, 1.0});
    tol.live_match = m.number_or("live_match", 1.0, {0.0, 1.0});
    tol.time_us =
        from_seconds(m.number_or("time_tolerance_ms", 0.0, config::Range::at_least(0.0)) * 1e-3);
    for (const char* info : {"launch_file", "log", "written_by"})
      if (auto v = m.find(info)) v->mark_used();
    if (auto ps = m.find("processes")) {
      if (!ps->is_map()) ps->fail("a map of process name: config (or {program, config, args})");
      plan.from_manifest = true;
      for (const auto& k : ps->keys()) plan_manifest_process(plan, req, k, ps->at(k));
    }
    m.check_all_used();
  }
  if (req.tolerance) tol.abs = *req.tolerance;
  if (req.relative_tolerance) tol.rel = *req.relative_tolerance;
  if (req.live_match) tol.live_match = *req.live_match;
  if (req.time_tolerance_ms) tol.time_us = from_seconds(*req.time_tolerance_ms * 1e-3);
  if (plan.live && tol.time_us == 0) tol.time_us = 20'000;  // a live log's times: the wall clock's
  return plan;
}

void plan_from_log(ReplayPlan& plan, const ReplayRequest& req, const std::vector<Event>& log) {
  const std::string& which = req.process;
  if (!plan.from_manifest) {
    std::set<std::string> hbs;  // the heartbeat channels in the log: the processes that ran
    for (const auto& ev : log)
      if (ev.channel.rfind(channels::kHeartbeatPrefix, 0) == 0) hbs.insert(ev.channel);
    for (const auto& e : replayable_processes()) {
      if (which != "all" && e.name != which) continue;
      if (which == "all" && hbs.count(heartbeat_channel_of(e.name)) == 0) continue;
      plan.processes.push_back(Planned{&e, e.default_config, {}});
    }
    // Processes that ran but cannot be replayed: say so.
    if (which == "all") {
      for (const auto& hb : hbs) {
        bool known = false;
        for (const auto& e : replayable_processes())
          known = known || heartbeat_channel_of(e.name) == hb;
        if (known) continue;
        std::string name = hb.substr(std::string(channels::kHeartbeatPrefix).size());
        for (char& c : name)
          c = c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        plan.skipped.push_back(name + " (its heartbeat is in the log: not a replayable process)");
      }
    }
  }
  if (req.config) {
    if (which == "all") throw std::runtime_error("--config needs --process NAME");
    if (plan.processes.empty()) plan.processes.push_back(Planned{replayable(which), "", {}});
    for (auto& p : plan.processes) p.config = *req.config;
  }
  // Processes whose config is the vehicle's have no default.
  for (auto it = plan.processes.begin(); it != plan.processes.end();) {
    if (!it->config.empty()) {
      ++it;
      continue;
    }
    if (which != "all")
      throw std::runtime_error(it->entry->name +
                               " has no default config (it is the vehicle's): give --config FILE "
                               "or a manifest (--configs)");
    plan.skipped.push_back(it->entry->name +
                           " (needs its vehicle's config: a manifest or --process " +
                           it->entry->name + " --config FILE)");
    it = plan.processes.erase(it);
  }
  // Recorded paths are relative to the tree the run was started in.
  for (auto& p : plan.processes) {
    for (auto& s : p.args) {
      const auto eq = s.find('=');
      const std::string v = eq == std::string::npos ? s : s.substr(eq + 1);
      const bool path_like = !v.empty() && v[0] != '-' && v.find('/') != std::string::npos;
      const std::string r = path_like ? plan.resolve(v) : v;
      s = eq == std::string::npos ? r : s.substr(0, eq + 1) + r;
    }
  }
}

bool run_plan(const ReplayPlan& plan, const std::vector<Event>& log, std::size_t show,
              std::ostream& out) {
  for (const auto& s : plan.skipped) out << "skipped: " << s << "\n";
  if (plan.processes.empty()) {
    out << std::flush;
    throw std::runtime_error(
        (plan.process == "all" ? "no replayable process ran in " + plan.log_path +
                                     (plan.from_manifest ? " (manifest " + plan.manifest + ")" : "")
                               : plan.process + " is not among the processes of " + plan.manifest) +
        " (see --list)");
  }
  const Tolerance& tol = plan.tol;
  bool ok = true;
  // The verdict names what it covers: on a live log the integrating processes are replayed
  // and reported but are not in it (see format_report).
  std::vector<std::string> checked, informational;
  for (const Planned& p : plan.processes) {
    ReplayOptions o;
    o.heartbeats = plan.heartbeats && !plan.live;
    o.live = plan.live;
    o.show = show;
    o.args = p.args;
    const auto rep = replay_process(*p.entry, plan.resolve(p.config), log, tol, o);
    out << format_report(rep);
    ok = ok && rep.ok();
    (rep.informational ? informational : checked).push_back(p.entry->name);
  }
  const auto listed = [](const std::vector<std::string>& ns) {
    std::string s;
    for (const auto& n : ns) s += (s.empty() ? "" : ", ") + n;
    return s;
  };
  out << "tiller-replay: " << (ok ? "PASS" : "FAIL") << " (" << checked.size()
      << (checked.size() == 1 ? " process" : " processes") << " checked"
      << (checked.empty() ? "" : ": " + listed(checked))
      << (informational.empty() ? ""
                                : "; " + std::to_string(informational.size()) +
                                      " informational: " + listed(informational))
      << (plan.live ? "; live log: ticks aligned to the recording" : "") << "; tolerance "
      << tol.abs << (tol.rel > 0 ? " + " + std::to_string(tol.rel) + " x |old|" : "")
      << (plan.live && tol.live_match < 1
              ? ", " + std::to_string(static_cast<int>(std::lround(tol.live_match * 100))) +
                    "% of messages"
              : "")
      << ", time tolerance " << to_seconds(tol.time_us) * 1e3 << " ms"
      << (plan.skipped.empty() ? "" : ", " + std::to_string(plan.skipped.size()) + " skipped")
      << ")\n";
  return ok;
}

}  // namespace tiller::replaytool
