#include "launch/plan.hpp"

#include <algorithm>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include "runtime/heartbeat_name.hpp"

namespace tiller::launch {

namespace {
// YAML double-quoted scalar.
std::string q(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

ProcessSpec logger_process(const LoggerSpec& l, const std::string& lcm_url,
                           const std::string& log_file) {
  ProcessSpec lg;
  lg.name = "logger";
  lg.command = "lcm-logger";
  lg.group = "logger";
  lg.args = {"--quiet", "--channel=" + l.channels};
  if (l.split_mb > 0) lg.args.push_back("--split-mb=" + std::to_string(l.split_mb));
  if (l.rotate > 0) {
    lg.args.push_back("--rotate=" + std::to_string(l.rotate));  // FILE.0, FILE.1, ...
  } else if (l.split_mb > 0) {
    lg.args.push_back("--increment");  // FILE.00, FILE.01, ...
  }
  // lcm-logger 1.3.1: -l is broken, and --lcm-url before --split-mb loses the file name; so
  // --lcm-url= comes last before the file.
  lg.args.push_back("--lcm-url=" + lcm_url);
  lg.args.push_back(log_file);
  lg.restart = Restart::kOnFailure;
  lg.liveness_s = 0;  // lcm-logger publishes no heartbeat
  return lg;
}
}  // namespace

Plan make_plan(LaunchFile lf, const LaunchChoices& c, const std::string& stamp,
               const std::string& cwd) {
  Plan plan;
  if (c.lcm_url) lf.lcm_url = *c.lcm_url;
  const std::vector<std::size_t> chosen = select(lf, c.groups, c.only);
  for (std::size_t i = 0; i < lf.processes.size(); ++i) {
    const auto& p = lf.processes[i];
    if (std::find(chosen.begin(), chosen.end(), i) == chosen.end() && !p.autostart)
      plan.held_back.push_back(p.name + " (autostart: false; start it with --group " + p.group +
                               " or --only " + p.name + ")");
  }
  plan.log = lf.logger.enabled && !c.no_log;
  std::string log_dir = c.log_dir.empty() ? lf.logger.dir : c.log_dir;
  if (!log_dir.empty() && log_dir[0] != '/') log_dir = lf.root + "/" + log_dir;
  std::string& log_file = plan.log_file;
  log_file = c.log_file;
  // With rotate the name is fixed, so lcm-logger's rotation also bounds the files of past runs
  // (logs/<name>.lcmlog.0 is the newest); otherwise one file (or split parts) per run.
  if (log_file.empty() && lf.logger.rotate > 0)
    log_file = log_dir + "/" + lf.name + ".lcmlog";
  else if (log_file.empty())
    log_file = log_dir + "/" + stamp + ".lcmlog";
  else if (log_file[0] != '/')
    log_file = cwd + "/" + log_file;

  if (plan.log) plan.procs.push_back(logger_process(lf.logger, lf.lcm_url, log_file));
  for (std::size_t i : chosen) plan.procs.push_back(lf.processes[i]);
  if (plan.log && plan.procs.size() > 1) {  // the logger subscribes first, and has written
    plan.procs[1].start_delay_s = std::max(plan.procs[1].start_delay_s, 0.3);
    plan.procs[1].start_after_file = log_file + log_suffix(lf.logger);
  }
  plan.lf = std::move(lf);
  return plan;
}

std::string log_suffix(const LoggerSpec& l) {
  return l.rotate > 0 ? ".0" : l.split_mb > 0 ? ".00" : "";
}

std::string rotate_previous_logs(const std::string& log_file, int rotate) {
  namespace fs = std::filesystem;
  std::string problems;
  std::error_code ec;
  for (int k = rotate - 1; k >= 0; --k) {
    const fs::path from = log_file + "." + std::to_string(k);
    if (!fs::exists(from, ec)) continue;
    if (k == rotate - 1) {
      fs::remove(from, ec);
    } else {
      fs::rename(from, log_file + "." + std::to_string(k + 1), ec);
    }
    if (ec) problems += "cannot move " + from.string() + " out of the way: " + ec.message() + "\n";
  }
  return problems;
}

std::string log_stem(const std::string& log_file) {
  const std::string ext = ".lcmlog";
  if (log_file.size() > ext.size() &&
      log_file.compare(log_file.size() - ext.size(), ext.size(), ext) == 0)
    return log_file.substr(0, log_file.size() - ext.size());
  return log_file;
}

std::string default_status_file(const std::string& launch_name, const std::string& runtime_dir) {
  return (runtime_dir.empty() ? std::string("/tmp") : runtime_dir) + "/tiller-launch-" +
         launch_name + ".status";
}

void write_manifest(std::ostream& m, const Plan& plan, const PosixHost& host) {
  const LaunchFile& lf = plan.lf;
  m << "# tiller-replay manifest of " << plan.log_file << "\n"
    << "# written by tiller-launch from " << lf.path << ". A live log: the processes ran on the\n"
    << "# wall clock, so tiller-replay runs each tick where the recording shows it ran, matches\n"
    << "# messages by nearest time (within 20 ms) and needs live_match of each channel's messages\n"
    << "# within tolerance + relative_tolerance x |old| (the rest: ticks that saw an input in\n"
    << "# another order than live).\n"
    << "written_by: tiller-launch\n"
    << "launch_file: " << q(lf.path) << "\n"
    << "log: " << q(plan.log_file) << "\n"
    << "root: " << q(lf.root) << "\n"
    << "live: true\n"
    << "time_tolerance_ms: 20\n"
    << "tolerance: 0.01\n"
    << "relative_tolerance: 0.02\n"
    << "live_match: 0.85\n"
    << "processes:\n";
  for (const auto& p : plan.procs) {
    if (p.name == "logger" && p.command == "lcm-logger") continue;
    const auto argv = host.argv_of(p);
    std::string config;
    for (std::size_t k = 1; k < argv.size(); ++k) {
      if (argv[k] == "--config" && k + 1 < argv.size()) config = argv[k + 1];
      if (argv[k].rfind("--config=", 0) == 0) config = argv[k].substr(9);
    }
    m << "  " << p.name << ":\n    program: " << q(argv[0]) << "\n";
    if (!config.empty()) m << "    config: " << q(config) << "\n";
    m << "    args: [";
    for (std::size_t k = 1; k < argv.size(); ++k) m << (k > 1 ? ", " : "") << q(argv[k]);
    m << "]\n";
  }
}

void print_check(std::ostream& out, const Plan& plan, const PosixHost& host) {
  const LaunchFile& lf = plan.lf;
  out << lf.path << ": " << lf.name << " (" << lf.description << ")\n  root " << lf.root
      << "\n  lcm  " << lf.lcm_url << (plan.signing.empty() ? "" : "\n  " + plan.signing)
      << "\n  ends with: " << (lf.ends_with.empty() ? "(Ctrl-C)" : lf.ends_with) << "\n";
  for (const auto& p : plan.procs) {
    const auto argv = host.argv_of(p);
    out << "  [" << p.group << "] " << p.name << ": " << host.resolve(argv[0]);
    for (std::size_t k = 1; k < argv.size(); ++k) out << " " << argv[k];
    out << "  (restart " << to_string(p.restart);
    if (p.liveness_s > 0)
      out << ", liveness " << p.liveness_s << " s on " << heartbeat_channel_of(p.heartbeat_node());
    out << ")\n";
  }
  for (const auto& h : plan.held_back) out << "  not started: " << h << "\n";
}

bool check_programs(const Plan& plan, const PosixHost& host, std::ostream& err) {
  bool ok = true;
  for (const auto& p : plan.procs) {
    try {
      const auto a = host.argv_of(p);
      if (host.resolve(a[0]).empty()) {
        err << "tiller-launch: " << plan.lf.path << ":" << p.line << ": " << p.name
            << ".command: expected a program next to tiller-launch or on PATH, got \"" << a[0]
            << "\"\n";
        ok = false;
      }
    } catch (const std::exception& e) {
      err << "tiller-launch: " << plan.lf.path << ":" << p.line << ": " << p.name << ": "
          << e.what() << "\n";
      ok = false;
    }
  }
  return ok;
}

}  // namespace tiller::launch
