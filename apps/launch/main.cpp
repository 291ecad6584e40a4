// tiller-launch: starts the processes of a launch file (config/launch/*.yaml), prefixes their
// output with their names, restarts them per policy, logs the run with lcm-logger, and stops
// everything in reverse order on Ctrl-C / SIGTERM or when the run's `ends_with` process exits.
// Exit status: 0 clean, 1 the run failed, 2 bad launch file or usage, 3 a critical process failed.
#include <poll.h>
#include <sys/prctl.h>
#include <sys/signalfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/config.hpp"
#include "launch/launch_file.hpp"
#include "launch/posix_host.hpp"
#include "launch/signing.hpp"
#include "launch/supervisor.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

using namespace tiller;
using namespace tiller::launch;

namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// What lcm-logger appends to the file name: .0 with rotate (the newest), .00 with split parts.
std::string log_suffix(const LoggerSpec& l) {
  return l.rotate > 0 ? ".0" : l.split_mb > 0 ? ".00" : "";
}
std::string logtools_stem(const std::string& log_file) {
  const std::string ext = ".lcmlog";
  if (log_file.size() > ext.size() &&
      log_file.compare(log_file.size() - ext.size(), ext.size(), ext) == 0)
    return log_file.substr(0, log_file.size() - ext.size());
  return log_file;
}

std::string default_status_file(const std::string& launch_name) {
  const char* run = std::getenv("XDG_RUNTIME_DIR");
  return std::string(run && *run ? run : "/tmp") + "/tiller-launch-" + launch_name + ".status";
}

std::string now_stamp() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%d-%H%M%S", &tm);
  return buf;
}

// YAML double-quoted scalar.
std::string q(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}

// The replay manifest of a run (tiller-replay reads LOG.replay.yaml next to LOG): what each
// process ran with, from the launch file's entries after ${...} substitution.
void write_manifest(const std::string& path, const LaunchFile& lf, const std::string& log_file,
                    const std::vector<ProcessSpec>& procs, const PosixHost& host) {
  std::ofstream m(path);
  m << "# tiller-replay manifest of " << log_file << "\n"
    << "# written by tiller-launch from " << lf.path << ". A live log: the processes ran on the\n"
    << "# wall clock, so tiller-replay runs each tick where the recording shows it ran, matches\n"
    << "# messages by nearest time (within 20 ms) and needs live_match of each channel's messages\n"
    << "# within tolerance + relative_tolerance x |old| (the rest: ticks that saw an input in\n"
    << "# another order than live).\n"
    << "written_by: tiller-launch\n"
    << "launch_file: " << q(lf.path) << "\n"
    << "log: " << q(log_file) << "\n"
    << "root: " << q(lf.root) << "\n"
    << "live: true\n"
    << "time_tolerance_ms: 20\n"
    << "tolerance: 0.01\n"
    << "relative_tolerance: 0.02\n"
    << "live_match: 0.85\n"
    << "processes:\n";
  for (const auto& p : procs) {
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
  if (!m) throw std::runtime_error("cannot write the replay manifest " + path);
}

bool explicit_option(int argc, char** argv, const std::string& name) {
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--" + name || s.rfind("--" + name + "=", 0) == 0) return true;
  }
  return false;
}

int run(int argc, char** argv) {
  const app::Spec spec{
      "tiller-launch",
      "Starts the processes of a launch file, logs the run, stops them cleanly.\n"
      "Usage: tiller-launch [options] LAUNCH_FILE (or --config LAUNCH_FILE) | tiller-launch status "
      "LAUNCH_FILE\n"
      "Exit status: 0 clean, 1 the run failed, 2 bad launch file or usage, 3 a critical process "
      "failed.",
      "",
      {{"group", "G[,G..]", "start only the processes of these groups", ""},
       {"only", "NAME[,NAME..]", "start only these processes (with --group: either)", ""},
       {"check", "", "check the launch file and the programs it names, print the plan, exit", ""},
       {"no-log", "", "do not start lcm-logger", ""},
       {"log-dir", "DIR", "directory for the log (default: the launch file's logger.dir)", ""},
       {"log-file", "FILE", "exact log file name (default: <log-dir>/<date-time>.lcmlog)", ""},
       {"status-every", "S",
        "print the status table every S seconds (0: only at the end and on SIGUSR1)", "0"},
       {"status-file", "FILE",
        "status table kept up to date here (default: $XDG_RUNTIME_DIR or /tmp)", ""}}};
  const app::Args args = app::parse(argc, argv, spec);
  // Checked before anything starts.
  const double every =
      app::number_option(args, "status-every", 0, 86400, "a number of seconds from 0 to 86400");
  if (args.positional.size() == 2 && args.positional[0] == "status") {
    const LaunchFile lf = load_launch_file(args.positional[1]);
    const std::string f =
        args.get("status-file").empty() ? default_status_file(lf.name) : args.get("status-file");
    std::ifstream in(f);
    if (!in) {
      std::cerr << "tiller-launch: no status at " << f << " (is " << lf.name << " running?)\n";
      return 1;
    }
    std::cout << in.rdbuf();
    return 0;
  }
  // The launch file: the one positional argument, or --config FILE.
  if (args.positional.size() > 1 || (args.positional.empty() && args.config.empty())) {
    std::cerr << "tiller-launch: give one launch file (see --help)\n";
    return kExitUsage;
  }
  LaunchFile lf = load_launch_file(args.positional.empty() ? args.config : args.positional[0]);
  if (explicit_option(argc, argv, "lcm-url")) lf.lcm_url = with_default_ttl(args.lcm_url);
  std::vector<std::size_t> chosen;
  try {
    chosen = select(lf, split_list(args.get("group")), split_list(args.get("only")));
  } catch (const std::invalid_argument& e) {
    std::cerr << "tiller-launch: " << e.what() << "\n";
    return kExitUsage;
  }

  std::vector<std::string> held_back;
  for (std::size_t i = 0; i < lf.processes.size(); ++i) {
    if (std::find(chosen.begin(), chosen.end(), i) == chosen.end() && !lf.processes[i].autostart)
      held_back.push_back(lf.processes[i].name + " (autostart: false; start it with --group " +
                          lf.processes[i].group + " or --only " + lf.processes[i].name + ")");
  }

  // The run's log.
  const bool log = lf.logger.enabled && !args.flag("no-log");
  std::string log_dir = args.get("log-dir").empty() ? lf.logger.dir : args.get("log-dir");
  if (!log_dir.empty() && log_dir[0] != '/') log_dir = lf.root + "/" + log_dir;
  std::string log_file = args.get("log-file");
  // With rotate the name is fixed, so lcm-logger's rotation also bounds the files of past runs
  // (logs/<name>.lcmlog.0 is the newest); otherwise one file (or split parts) per run.
  if (log_file.empty() && lf.logger.rotate > 0)
    log_file = log_dir + "/" + lf.name + ".lcmlog";
  else if (log_file.empty())
    log_file = log_dir + "/" + now_stamp() + ".lcmlog";
  else if (log_file[0] != '/')
    log_file = std::filesystem::absolute(log_file).string();

  std::vector<ProcessSpec> procs;
  if (log) {
    ProcessSpec lg;
    lg.name = "logger";
    lg.command = "lcm-logger";
    lg.group = "logger";
    lg.args = {"--quiet", "--channel=" + lf.logger.channels};
    if (lf.logger.split_mb > 0)
      lg.args.push_back("--split-mb=" + std::to_string(lf.logger.split_mb));
    if (lf.logger.rotate > 0) {
      lg.args.push_back("--rotate=" + std::to_string(lf.logger.rotate));  // FILE.0, FILE.1, ...
    } else if (lf.logger.split_mb > 0) {
      lg.args.push_back("--increment");  // FILE.00, FILE.01, ...
    }
    // lcm-logger 1.3.1: -l is broken, and --lcm-url before --split-mb loses the file name; so
    // --lcm-url= comes last before the file.
    lg.args.push_back("--lcm-url=" + lf.lcm_url);
    lg.args.push_back(log_file);
    lg.restart = Restart::kOnFailure;
    procs.push_back(lg);
  }
  for (std::size_t i : chosen) procs.push_back(lf.processes[i]);
  if (log && procs.size() > 1)
    procs[1].start_delay_s = std::max(procs[1].start_delay_s, 0.3);  // logger subscribes first

  std::size_t width = 6;
  for (const auto& p : procs) width = std::max(width, p.name.size());
  const std::map<std::string, std::string> vars{
      {"LCM_URL", lf.lcm_url}, {"ROOT", lf.root}, {"LOG_FILE", log_file}, {"LAUNCH_NAME", lf.name}};
  // Every child gets the LCM URL and the signing settings (key checked now, before any start).
  std::map<std::string, std::string> child_env{{"LCM_DEFAULT_URL", lf.lcm_url}};
  try {
    if (explicit_option(argc, argv, "require-signed")) lf.require_signed = true;
    const auto sign_env = signing_env(
        lf, vars, explicit_option(argc, argv, "key-file") ? args.auth.key_file : "", std::cout);
    child_env.insert(sign_env.begin(), sign_env.end());
  } catch (const std::exception& e) {
    std::cerr << "tiller-launch: " << e.what() << "\n";
    return kExitUsage;
  }
  PosixHost host(lf.root, vars, {self_dir()}, child_env, stdout, width);
  const std::string signing =
      child_env.count("TILLER_KEY_FILE")
          ? "signing: key " + child_env["TILLER_KEY_FILE"] +
                (lf.require_signed ? ", unsigned input refused" : ", unsigned input accepted")
          : "signing: off (no key_file)";

  // Refuse a plan whose programs do not exist, naming the line.
  bool bad = false;
  for (const auto& p : procs) {
    try {
      const auto a = host.argv_of(p);
      if (host.resolve(a[0]).empty()) {
        std::cerr << "tiller-launch: " << lf.path << ":" << p.line << ": " << p.name
                  << ".command: expected a program next to tiller-launch or on PATH, got \"" << a[0]
                  << "\"\n";
        bad = true;
      }
    } catch (const std::exception& e) {
      std::cerr << "tiller-launch: " << lf.path << ":" << p.line << ": " << p.name << ": "
                << e.what() << "\n";
      bad = true;
    }
  }
  if (bad) return kExitUsage;
  if (args.flag("check")) {
    std::cout << lf.path << ": " << lf.name << " (" << lf.description << ")\n  root " << lf.root
              << "\n  lcm  " << lf.lcm_url << "\n  " << signing
              << "\n  ends with: " << (lf.ends_with.empty() ? "(Ctrl-C)" : lf.ends_with) << "\n";
    for (const auto& p : procs) {
      std::cout << "  [" << p.group << "] " << p.name << ": " << host.resolve(host.argv_of(p)[0]);
      for (std::size_t k = 1; k < host.argv_of(p).size(); ++k)
        std::cout << " " << host.argv_of(p)[k];
      std::cout << "  (restart " << to_string(p.restart) << ")\n";
    }
    for (const auto& h : held_back) std::cout << "  not started: " << h << "\n";
    return kExitOk;
  }
  if (log) {
    std::filesystem::create_directories(std::filesystem::path(log_file).parent_path());
    const std::string manifest = logtools_stem(log_file) + ".replay.yaml";
    write_manifest(manifest, lf, log_file, procs, host);
  }

  // Signals arrive through a signalfd; children get them unblocked before exec.
  sigset_t mask;
  sigemptyset(&mask);
  for (int s : {SIGCHLD, SIGINT, SIGTERM, SIGHUP, SIGUSR1}) sigaddset(&mask, s);
  ::sigprocmask(SIG_BLOCK, &mask, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
  const int sfd = ::signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
  ::prctl(PR_SET_CHILD_SUBREAPER, 1);  // orphaned grandchildren come back to us to be reaped
  {
    std::string guard_error;
    if (host.start_guard(guard_error) < 0)
      host.print("launch", "warning: no guard for grandchildren (" + guard_error +
                               "): if tiller-launch is killed, their children may survive");
  }

  const std::string status_file =
      args.get("status-file").empty() ? default_status_file(lf.name) : args.get("status-file");
  auto note = [&](const std::string& s) { host.print("launch", s); };
  Supervisor sup(procs, lf.ends_with, lf.grace_s, host, note);
  host.print("launch", lf.name + ": " + std::to_string(procs.size()) + " processes, lcm " +
                           lf.lcm_url + ", " + signing);
  for (const auto& h : held_back) host.print("launch", "not started: " + h);
  if (log)
    host.print("launch", "log: " + log_file + log_suffix(lf.logger) + " (replay manifest " +
                             logtools_stem(log_file) + ".replay.yaml)");
  const TimeUs t0 = wall_time_us();
  sup.start(t0);

  TimeUs next_status = every > 0 ? t0 + from_seconds(every) : INT64_MAX;
  TimeUs next_file = t0;
  int interrupts = 0;
  TimeUs drain_until = INT64_MAX;
  for (;;) {
    TimeUs now = wall_time_us();
    if (now >= next_file) {
      std::ofstream(status_file) << lf.name << " at " << now_stamp()
                                 << (sup.stopping() ? " (stopping)" : "") << "\n"
                                 << sup.status_table(now);
      next_file = now + kUsPerSecond;
    }
    if (now >= next_status) {
      std::cout << sup.status_table(now) << std::flush;
      next_status = now + from_seconds(every);
    }
    if (sup.finished() && drain_until == INT64_MAX) drain_until = now + 200'000;
    const auto fds = host.output_fds();
    if (sup.finished() && (fds.empty() || now >= drain_until)) break;
    TimeUs wake =
        std::min({sup.next_deadline(), next_status, next_file, drain_until, now + kUsPerSecond});
    const int timeout_ms = static_cast<int>(std::clamp<TimeUs>((wake - now + 999) / 1000, 0, 1000));
    std::vector<pollfd> pfds{{sfd, POLLIN, 0}};
    for (int fd : fds) pfds.push_back({fd, POLLIN, 0});
    ::poll(pfds.data(), pfds.size(), timeout_ms);
    now = wall_time_us();
    for (std::size_t k = 1; k < pfds.size(); ++k) {
      if (pfds[k].revents) host.on_readable(pfds[k].fd);
    }
    signalfd_siginfo si{};
    while (::read(sfd, &si, sizeof si) == static_cast<ssize_t>(sizeof si)) {
      const int sig = static_cast<int>(si.ssi_signo);
      if (sig == SIGCHLD) {
        int st = 0;
        pid_t pid;
        while ((pid = ::waitpid(-1, &st, WNOHANG)) > 0) {
          ExitInfo e;
          if (WIFEXITED(st)) e.code = WEXITSTATUS(st);
          if (WIFSIGNALED(st)) e.signal = WTERMSIG(st);
          sup.on_exit(pid, e, now);
        }
      } else if (sig == SIGUSR1) {
        std::cout << sup.status_table(now) << std::flush;
      } else {
        ++interrupts;
        if (interrupts == 1) {
          sup.request_stop(now, std::string("SIG") + sigabbrev_np(sig), kExitOk);
        } else {
          note("second SIG" + std::string(sigabbrev_np(sig)) + ": SIGKILL to everything");
          for (const auto& p : sup.processes()) host.signal(p.pid, SIGKILL);
        }
      }
    }
    sup.poll(now);
  }
  const TimeUs end = wall_time_us();
  std::cout << sup.status_table(end);
  std::ofstream(status_file) << lf.name << " finished at " << now_stamp() << ": "
                             << sup.stop_reason() << "\n"
                             << sup.status_table(end);
  if (log) {
    std::cout << "tiller-launch: log " << log_file << log_suffix(lf.logger)
              << (lf.logger.split_mb > 0
                      ? (lf.logger.rotate > 0 ? " (the newest part; older: .1, .2, ...)"
                                              : " (and following parts)")
                      : "")
              << "\n";
  }
  std::cout << "tiller-launch: " << sup.stop_reason() << "; exit status " << sup.exit_status()
            << "\n";
  return sup.exit_status();
}

}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-launch", [&] { return run(argc, argv); });
}
