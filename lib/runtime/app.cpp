#include "runtime/app.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "core/config.hpp"
#include "core/lcm_url.hpp"
#include "runtime/channels.hpp"
#include "runtime/realtime.hpp"

namespace tiller::app {

const std::string& Args::get(const std::string& name) const {
  static const std::string empty;
  auto it = values.find(name);
  return it == values.end() ? empty : it->second;
}

bool Args::flag(const std::string& name) const {
  auto it = values.find(name);
  return it != values.end() && !it->second.empty() && it->second != "0";
}

namespace {
std::string usage_line(const Spec& spec) {
  return "Usage: " + spec.program + " [options]" +
         (spec.arguments.empty() ? "" : " " + spec.arguments);
}

void help(const Spec& spec, std::ostream& os) {
  os << usage_line(spec) << "\n" << spec.summary << "\n\nOptions:\n";
  auto line = [&](std::string lhs, const std::string& text, const std::string& default_value) {
    if (lhs.size() < 20) lhs.resize(20, ' ');
    os << "  " << lhs << " " << text;
    if (!default_value.empty()) os << " (default: " << default_value << ")";
    os << "\n";
  };
  line("--help", "show this help and exit", "");
  if (spec.takes_config) line("--config FILE", spec.config_help, spec.default_config);
  if (spec.takes_lcm_url)
    line("--lcm-url URL", "LCM URL; ttl=0 is added unless the URL sets ttl",
         std::string("$LCM_DEFAULT_URL, else ") + channels::kDefaultLcmUrl);
  if (spec.takes_lcm_url && spec.takes_realtime) {
    line("--realtime-priority N", "run with SCHED_FIFO priority N (1..99; docs/operations.md)", "");
    line("--lock-memory", "lock all memory (mlockall) so the loop never waits on a page fault", "");
    line("--realtime-required", "refuse to start when the two above are not permitted", "");
  }
  for (const auto& o : spec.options)
    line("--" + o.name + (o.value_name.empty() ? "" : " " + o.value_name), o.help, o.default_value);
}

// The positional argument at `index` is one too many: its message, or "" when it is taken.
std::string extra_positional(const Spec& spec, const std::vector<std::string>& positional) {
  if (positional.empty()) return "";
  std::size_t max = spec.max_positional;
  if (auto c = spec.commands.find(positional[0]); c != spec.commands.end()) max = 1 + c->second;
  if (positional.size() <= max) return "";
  const std::string& extra = positional[max];
  std::string takes;
  if (max == 0 && !spec.commands.empty()) {
    for (const auto& [name, n] : spec.commands) takes += (takes.empty() ? "" : ", ") + name;
    takes = "commands: " + takes;
  } else {
    takes = spec.program + " takes " +
            (spec.arguments.empty() ? "no positional arguments" : spec.arguments);
  }
  return "unexpected argument '" + extra + "' (" + takes + ")";
}
}  // namespace

namespace {
[[noreturn]] void bad_option(const std::string& name, const std::string& expected,
                             const std::string& value) {
  throw std::runtime_error("--" + name + ": expected " + expected + ", got '" + value + "'");
}
}  // namespace

double number_option(const Args& a, const std::string& name, double lo, double hi,
                     const std::string& expected) {
  const std::string& s = a.get(name);
  double v = NAN;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v) || v < lo ||
      v > hi)
    bad_option(name, expected, s);
  return v;
}

std::int64_t integer_option(const Args& a, const std::string& name, std::int64_t lo,
                            std::int64_t hi, const std::string& expected) {
  const std::string& s = a.get(name);
  std::int64_t v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || p != s.data() + s.size() || v < lo || v > hi)
    bad_option(name, expected, s);
  return v;
}

std::string resolve_path(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty() || fs::path(path).is_absolute() || fs::exists(path)) return path;
  for (const char* base : {TILLER_SOURCE_DIR "/", TILLER_SOURCE_DIR "/config/"}) {
    const std::string candidate = base + path;
    if (fs::exists(candidate)) return candidate;
  }
  return path;
}

namespace {
// --key-file / --require-signed / --auth-window-s / --clock-offset-s, or their variables: the
// signing policy and the clock offset bound on message stamps.
// A bad value or key file is a start-up error (exit 2) naming it.
void load_auth(Args& a, const Spec& spec, const std::string& key_file, const std::string& require,
               const std::string& window, const std::string& clock_offset) {
  auto fail = [&](const std::string& msg) {
    std::cerr << spec.program << ": " << msg << "\n";
    std::exit(2);
  };
  a.auth.raw_sender = spec.program.rfind("tiller-", 0) == 0 ? spec.program.substr(7) : spec.program;
  if (a.auth.raw_sender.size() > 16) a.auth.raw_sender.resize(16);
  if (require == "1" || require == "true") {
    a.auth.require_signed = true;
  } else if (!require.empty() && require != "0" && require != "false") {
    fail("TILLER_REQUIRE_SIGNED: expected 1, true, 0 or false, got '" + require + "'");
  }
  if (!window.empty()) {
    double w = NAN;
    const auto [p, ec] = std::from_chars(window.data(), window.data() + window.size(), w);
    if (ec != std::errc() || p != window.data() + window.size() || !std::isfinite(w) || w <= 0 ||
        w > 3600)
      fail(
          "--auth-window-s / TILLER_AUTH_WINDOW_S: expected a number of seconds in (0, 3600], "
          "got '" +
          window + "'");
    a.auth.window_us = static_cast<std::int64_t>(w * 1e6);
  }
  if (!clock_offset.empty()) {
    double c = NAN;
    const auto [p, ec] =
        std::from_chars(clock_offset.data(), clock_offset.data() + clock_offset.size(), c);
    if (ec != std::errc() || p != clock_offset.data() + clock_offset.size() || !std::isfinite(c) ||
        c < 0 || c > 10)
      fail(
          "--clock-offset-s / TILLER_CLOCK_OFFSET_S: expected a number of seconds in [0, 10], "
          "got '" +
          clock_offset + "'");
    a.auth.clock_offset_us = static_cast<std::int64_t>(c * 1e6 + 0.5);
  }
  if (!key_file.empty()) {
    try {
      a.auth.key = auth::load_key_file(key_file);
      a.auth.key_file = key_file;
    } catch (const std::exception& e) {
      fail(e.what());
    }
  }
  if (a.auth.require_signed && !a.auth.key) {
    fail(
        "require_signed is on but no key file was given (--key-file FILE, TILLER_KEY_FILE or "
        "the launch file's key_file; make one with tiller-key new FILE)");
  }
}

std::string env_or_empty(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

// --realtime-priority / --lock-memory / --realtime-required (runtime/realtime.hpp): applied
// now, before the program opens anything. A refusal is a warning line per problem, or, when
// required, a start-up error (exit 2).
void apply_realtime(const Spec& spec, const std::string& priority, bool lock, bool required) {
  realtime::Request r;
  if (!priority.empty()) {
    std::int64_t v = 0;
    const auto [p, ec] = std::from_chars(priority.data(), priority.data() + priority.size(), v);
    if (ec != std::errc() || p != priority.data() + priority.size() || v < 1 || v > 99) {
      std::cerr << spec.program
                << ": --realtime-priority: expected a whole number in [1, 99], got '" << priority
                << "'\n";
      std::exit(2);
    }
    r.priority = static_cast<int>(v);
  }
  r.lock_memory = lock;
  r.required = required;
  if (!r.any()) {
    if (required) {
      std::cerr << spec.program
                << ": --realtime-required needs --realtime-priority N and/or --lock-memory\n";
      std::exit(2);
    }
    return;
  }
  const realtime::Report rep = realtime::apply(r, realtime::os());
  realtime::set_process_report(rep);
  for (const auto& problem : rep.problems)
    std::cerr << spec.program << ": " << (required ? "error" : "warning")
              << ": real time: " << problem << "\n";
  if (!rep.granted() && required) {
    std::cerr << spec.program
              << ": not starting: real time is required (--realtime-required, the launch file's "
                 "realtime.required)\n";
    std::exit(2);
  }
  std::cerr << spec.program << ": real time: " << realtime::summary(rep)
            << (rep.granted() ? ""
                              : " (continuing without what was refused; the heartbeat says "
                                "realtime.refused = 1)")
            << "\n";
}
}  // namespace

Args parse(int argc, char** argv, const Spec& spec) {
  Args a;
  a.config = spec.default_config;
  const char* env_url = std::getenv("LCM_DEFAULT_URL");
  a.lcm_url = env_url ? env_url : channels::kDefaultLcmUrl;
  if (const std::string why = lcm_url_problem(a.lcm_url); !why.empty()) {
    std::cerr << spec.program << ": LCM_DEFAULT_URL: expected " << why << "\n";
    std::exit(2);
  }
  for (const auto& o : spec.options) {
    if (o.default_value.empty()) continue;
    a.values[o.name] = o.value_name == "FILE" ? resolve_path(o.default_value) : o.default_value;
  }
  auto bad = [&](const std::string& msg) {
    std::cerr << spec.program << ": " << msg << "\n"
              << usage_line(spec) << "\n(" << spec.program << " --help lists the options)\n";
    std::exit(2);
  };
  std::string key_file = env_or_empty("TILLER_KEY_FILE");
  std::string require = env_or_empty("TILLER_REQUIRE_SIGNED");
  std::string window = env_or_empty("TILLER_AUTH_WINDOW_S");
  std::string clock_offset = env_or_empty("TILLER_CLOCK_OFFSET_S");
  std::string rt_priority;
  bool rt_lock = false, rt_required = false;
  for (int i = 1; i < argc; ++i) {
    std::string s = argv[i];
    std::string value;
    bool has_value = false;
    if (auto eq = s.find('='); s.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = s.substr(eq + 1);
      s = s.substr(0, eq);
      has_value = true;
    }
    auto take = [&]() -> std::string {
      if (has_value) return value;
      if (i + 1 >= argc) bad("option " + s + " needs a value");
      return argv[++i];
    };
    if (s.rfind("--", 0) == 0 && s != "--") a.given.insert(s.substr(2));
    if (s == "--help" || s == "-h") {
      help(spec, std::cout);
      std::exit(0);
    } else if (s == "--config") {
      if (!spec.takes_config) {
        bad("--config is not taken: " + spec.program + " has no config file");
      }
      a.config = take();
    } else if (s == "--lcm-url") {
      if (!spec.takes_lcm_url) bad("--lcm-url is not taken: " + spec.program + " opens no LCM");
      a.lcm_url = take();
      if (const std::string why = lcm_url_problem(a.lcm_url); !why.empty())
        bad("--lcm-url: expected " + why);
    } else if (s == "--key-file" || s == "--require-signed" || s == "--auth-window-s" ||
               s == "--clock-offset-s") {
      if (!spec.takes_lcm_url) bad(s + " is not taken: " + spec.program + " opens no LCM");
      if (s == "--key-file") key_file = take();
      if (s == "--require-signed") require = has_value ? value : "1";
      if (s == "--auth-window-s") window = take();
      if (s == "--clock-offset-s") clock_offset = take();
    } else if (s == "--realtime-priority" || s == "--lock-memory" || s == "--realtime-required") {
      if (!spec.takes_lcm_url || !spec.takes_realtime)
        bad(s + " is not taken: " + spec.program + " runs no real-time loop of its own");
      if (s == "--realtime-priority") rt_priority = take();
      if (s == "--lock-memory") rt_lock = true;
      if (s == "--realtime-required") rt_required = true;
    } else if (s.rfind("--", 0) == 0) {
      const std::string name = s.substr(2);
      bool known = false;
      for (const auto& o : spec.options) {
        if (o.name != name) continue;
        known = true;
        a.values[name] = o.value_name.empty() ? "1" : take();
      }
      if (!known) bad("unknown option " + s);
    } else {
      a.positional.push_back(s);
    }
  }
  if (const std::string extra = extra_positional(spec, a.positional); !extra.empty()) bad(extra);
  a.config = resolve_path(a.config);
  if (spec.takes_lcm_url) load_auth(a, spec, key_file, require, window, clock_offset);
  if (spec.takes_lcm_url && spec.takes_realtime)
    apply_realtime(spec, rt_priority, rt_lock, rt_required);
  return a;
}

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = std::min(s.find(',', start), s.size());
    if (comma > start) out.push_back(s.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

int guarded_main(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const config::Error& e) {
    std::cerr << program << ": config error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
    return 2;
  }
}

}  // namespace tiller::app
