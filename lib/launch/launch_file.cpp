#include "launch/launch_file.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <stdexcept>

#include "core/config.hpp"
#include "core/lcm_url.hpp"
#include "runtime/channels.hpp"

namespace tiller::launch {

const char* to_string(Restart r) {
  switch (r) {
    case Restart::kNever:
      return "never";
    case Restart::kOnFailure:
      return "on-failure";
    case Restart::kAlways:
      return "always";
  }
  return "?";
}

namespace {

bool valid_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) return false;
  }
  return true;
}

std::vector<std::string> strings(const config::Value& v) {
  if (!v.is_sequence()) v.fail("a sequence of strings");
  std::vector<std::string> out;
  for (const auto& item : v.items()) out.push_back(item.as_string());
  return out;
}

// liveness_s: 0 (not watched) or long enough for 1 Hz heartbeats.
double liveness_of(const config::Value& v, double fallback) {
  const double s = v.number_or("liveness_s", fallback, {0.0, 3600.0});
  if (s != 0.0 && s < 1.5)
    v.at("liveness_s")
        .fail(
            "0 (not watched) or a number of seconds from 1.5 to 3600 "
            "(heartbeats come once a second)");
  return s;
}

// realtime: {priority, lock_memory, required} -> the spec, and its flags after the args.
void load_realtime(const config::Value& p, const config::Value& rt, ProcessSpec& s) {
  if (!rt.is_map()) rt.fail("a map (priority 1..99, lock_memory, required)");
  const auto slash = s.command.rfind('/');
  if (s.command.compare(slash == std::string::npos ? 0 : slash + 1, 7, "tiller-") != 0)
    p.at("command").fail("a tiller-* program with realtime: (the program applies it itself)");
  s.realtime.priority = static_cast<int>(rt.integer_or("priority", 0, 1, 99));
  s.realtime.lock_memory = rt.boolean_or("lock_memory", true);
  s.realtime.required = rt.boolean_or("required", false);
  if (!s.realtime.any()) rt.fail("priority: N or lock_memory: true (nothing to apply)");
  for (auto& a : realtime_args(s.realtime)) s.args.push_back(std::move(a));
}

ProcessSpec load_process(const config::Value& p, double liveness_s) {
  if (!p.is_map()) p.fail("a map with at least name and command");
  ProcessSpec s;
  s.line = p.line();
  s.name = p.string("name");
  if (!valid_name(s.name)) p.at("name").fail("a name of letters, digits, '-' and '_'");
  s.command = p.string("command");
  if (s.command.empty()) p.at("command").fail("a program name or path");
  if (auto a = p.find("args")) s.args = strings(*a);
  if (auto e = p.find("env")) {
    if (!e->is_map()) e->fail("a map of NAME: value");
    for (const auto& k : e->keys()) s.env[k] = e->at(k).as_string();
  }
  s.group = p.string_or("group", "default");
  if (auto d = p.find("depends_on")) s.depends_on = strings(*d);
  s.start_delay_s = p.number_or("start_delay_s", 0.0, {0.0, 600.0});
  const std::string r = p.choice_or("restart", "never", {"never", "on-failure", "always"});
  s.restart = r == "always"       ? Restart::kAlways
              : r == "on-failure" ? Restart::kOnFailure
                                  : Restart::kNever;
  s.backoff_s = p.number_or("backoff_s", 0.5, {0.01, 3600.0});
  s.backoff_max_s = p.number_or("backoff_max_s", 10.0, {0.01, 3600.0});
  if (s.backoff_max_s < s.backoff_s) p.at("backoff_max_s").fail("a number >= backoff_s");
  s.max_restarts = static_cast<int>(p.integer_or("max_restarts", 5, 0, 1000000));
  s.stable_after_s = p.number_or("stable_after_s", 30.0, {0.0, 86400.0});
  s.critical = p.boolean_or("critical", false);
  s.autostart = p.boolean_or("autostart", true);
  s.liveness_s = liveness_of(p, liveness_s);
  s.heartbeat = p.string_or("heartbeat", "");
  if (p.has("heartbeat") && !valid_name(s.heartbeat))
    p.at("heartbeat").fail("a node name of letters, digits, '-' and '_'");
  if (auto rt = p.find("realtime")) load_realtime(p, *rt, s);
  return s;
}

}  // namespace

std::vector<std::string> realtime_args(const RealtimeSpec& r) {
  std::vector<std::string> a;
  if (!r.any()) return a;
  if (r.priority > 0) a.push_back("--realtime-priority=" + std::to_string(r.priority));
  if (r.lock_memory) a.emplace_back("--lock-memory");
  if (r.required) a.emplace_back("--realtime-required");
  return a;
}

LaunchFile load_launch(const config::Value& root, const std::string& file_dir) {
  if (!root.is_map()) root.fail("a launch file (a map with processes:)");
  LaunchFile lf;
  lf.path = root.file();
  lf.name = root.string("name");
  lf.description = root.string_or("description", "");
  lf.lcm_url = root.string_or("lcm_url", channels::kDefaultLcmUrl);
  if (const std::string why = lcm_url_problem(lf.lcm_url); !why.empty()) {
    root.at("lcm_url").fail(why);
  }
  const std::string rel_root = root.string_or("root", "../..");
  std::error_code ec;
  auto abs_root = std::filesystem::weakly_canonical(std::filesystem::path(file_dir) / rel_root, ec);
  if (ec || !std::filesystem::is_directory(abs_root)) {
    if (root.has("root")) root.at("root").fail("a directory relative to the launch file");
    abs_root = std::filesystem::path(file_dir) / rel_root;
  }
  lf.root = abs_root.string();
  lf.grace_s = root.number_or("grace_s", 3.0, {0.05, 120.0});

  if (auto l = root.find("logger")) {
    if (!l->is_map()) l->fail("a map (enabled, dir, channels, split_mb, rotate)");
    lf.logger.enabled = l->boolean_or("enabled", true);
    lf.logger.dir = l->string_or("dir", "logs");
    lf.logger.channels = l->string_or("channels", ".*");
    lf.logger.split_mb = l->number_or("split_mb", 0.0, {0.0, 1e6});
    lf.logger.rotate = static_cast<int>(l->integer_or("rotate", 0, 0, 1000));
  }

  lf.key_file = root.string_or("key_file", "");
  if (root.has("key_file")) lf.key_file_line = root.at("key_file").line();
  lf.require_signed = root.boolean_or("require_signed", !lf.key_file.empty());
  lf.allow_unsigned = root.boolean_or("allow_unsigned", false);
  if (!lf.require_signed && !lf.key_file.empty() && !lf.allow_unsigned)
    root.at("require_signed")
        .fail(
            "true (false lets anyone on the network command the vehicle; if that is meant, "
            "say allow_unsigned: true as well)");
  lf.auth_window_s = root.number_or("auth_window_s", 1.0, {0.001, 3600.0});
  lf.clock_offset_s = root.number_or("clock_offset_s", 0.25, {0.0, 10.0});
  lf.create_key = root.boolean_or("create_key", false);
  if (lf.require_signed && lf.key_file.empty())
    root.at("require_signed").fail("key_file: FILE as well (require_signed needs a key)");
  if (lf.create_key && lf.key_file.empty()) root.at("create_key").fail("key_file: FILE as well");

  lf.liveness_s = liveness_of(root, 3.0);

  const config::Value procs = root.at("processes");
  if (!procs.is_sequence() || procs.size() == 0) procs.fail("a non-empty sequence of processes");
  std::vector<ProcessSpec> in_file;
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < procs.size(); ++i) {
    in_file.push_back(load_process(procs[i], lf.liveness_s));
    if (!index.emplace(in_file.back().name, i).second) {
      procs[i].at("name").fail("a name not used by another process");
    }
  }
  for (std::size_t i = 0; i < in_file.size(); ++i) {
    const auto deps = procs[i].find("depends_on");
    for (std::size_t k = 0; k < in_file[i].depends_on.size(); ++k) {
      const auto& d = in_file[i].depends_on[k];
      if (!index.count(d)) (*deps)[k].fail("the name of another process in this file");
      if (d == in_file[i].name) (*deps)[k].fail("another process (not itself)");
    }
  }
  // Start order: depth-first topological order, ties in file order; a cycle is an error.
  std::vector<int> mark(in_file.size(), 0);  // 0 new, 1 on stack, 2 done
  std::function<void(std::size_t)> visit = [&](std::size_t i) {
    if (mark[i] == 2) return;
    if (mark[i] == 1)
      procs[i]
          .at("depends_on")
          .fail("dependencies without a cycle (" + in_file[i].name +
                " depends on itself through others)");
    mark[i] = 1;
    for (const auto& d : in_file[i].depends_on) visit(index.at(d));
    mark[i] = 2;
    lf.processes.push_back(in_file[i]);
  };
  for (std::size_t i = 0; i < in_file.size(); ++i) visit(i);

  lf.ends_with = root.string_or("ends_with", "");
  if (!lf.ends_with.empty() && !index.count(lf.ends_with))
    root.at("ends_with").fail("the name of a process in this file");
  root.check_all_used();
  return lf;
}

LaunchFile load_launch_file(const std::string& path) {
  const auto v = config::Value::load_file(path);
  const auto dir = std::filesystem::absolute(std::filesystem::path(path)).parent_path().string();
  return load_launch(v, dir);
}

std::string substitute(const std::string& s, const std::map<std::string, std::string>& vars) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '$' && i + 1 < s.size() && s[i + 1] == '{') {
      const auto end = s.find('}', i + 2);
      if (end == std::string::npos) throw std::invalid_argument("unterminated ${ in \"" + s + "\"");
      std::string name = s.substr(i + 2, end - i - 2);
      std::optional<std::string> fallback;
      if (const auto dash = name.find(":-"); dash != std::string::npos) {
        fallback = name.substr(dash + 2);
        name = name.substr(0, dash);
      }
      const char* env = std::getenv(name.c_str());
      if (auto it = vars.find(name); it != vars.end()) {
        out += it->second;
      } else if (env && *env) {
        out += env;
      } else if (fallback) {
        // $NAME inside the fallback expands too (e.g. $XDG_CONFIG_HOME/tiller/sim.key).
        for (std::size_t k = 0; k < fallback->size(); ++k) {
          const char c = (*fallback)[k];
          std::size_t e = k + 1;
          while (
              e < fallback->size() &&
              (std::isalnum(static_cast<unsigned char>((*fallback)[e])) || (*fallback)[e] == '_'))
            ++e;
          if (c != '$' || e == k + 1) {
            out += c;
            continue;
          }
          const std::string v = fallback->substr(k + 1, e - k - 1);
          const char* ev = std::getenv(v.c_str());
          if (auto vt = vars.find(v); vt != vars.end()) {
            out += vt->second;
          } else if (ev && *ev) {
            out += ev;
          } else {
            throw std::invalid_argument("unknown variable $" + v + " in \"" + s + "\"");
          }
          k = e - 1;
        }
      } else {
        throw std::invalid_argument("unknown variable ${" + name + "} in \"" + s + "\"");
      }
      i = end;
    } else {
      out += s[i];
    }
  }
  return out;
}

std::vector<std::size_t> select(const LaunchFile& lf, const std::vector<std::string>& groups,
                                const std::vector<std::string>& names) {
  std::set<std::string> known_groups, known_names;
  for (const auto& p : lf.processes) {
    known_groups.insert(p.group);
    known_names.insert(p.name);
  }
  for (const auto& g : groups) {
    if (!known_groups.count(g)) throw std::invalid_argument("no group \"" + g + "\" in " + lf.path);
  }
  for (const auto& n : names) {
    if (!known_names.count(n))
      throw std::invalid_argument("no process \"" + n + "\" in " + lf.path);
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < lf.processes.size(); ++i) {
    const auto& p = lf.processes[i];
    const bool all = groups.empty() && names.empty() && p.autostart;
    const bool in_group = std::find(groups.begin(), groups.end(), p.group) != groups.end();
    const bool named = std::find(names.begin(), names.end(), p.name) != names.end();
    if (all || in_group || named) out.push_back(i);
  }
  return out;
}

}  // namespace tiller::launch
