// tiller-launch: starts the processes of a launch file (config/launch/*.yaml), prefixes their
// output with their names, restarts them per policy, logs the run with lcm-logger, and stops
// everything in reverse order on Ctrl-C / SIGTERM or when the run's `ends_with` process exits.
// The plan is launch/plan.hpp, the event loop launch/run.hpp.
// Exit status: 0 clean, 1 the run failed, 2 bad launch file or usage, 3 a critical process failed.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "auth/key.hpp"
#include "launch/launch_file.hpp"
#include "launch/plan.hpp"
#include "launch/posix_host.hpp"
#include "launch/run.hpp"
#include "launch/signing.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"

using namespace tiller;
using namespace tiller::launch;

namespace {

std::string status_file_of(const app::Args& args, const std::string& launch_name) {
  const char* run = std::getenv("XDG_RUNTIME_DIR");
  return args.get("status-file").empty() ? default_status_file(launch_name, run ? run : "")
                                         : args.get("status-file");
}

int run(int argc, char** argv) {
  app::Spec spec{
      "tiller-launch",
      "Starts the processes of a launch file (config/launch/*.yaml), logs the run, stops them\n"
      "cleanly. 'status LAUNCH_FILE' prints the status table of that launch's running instance.\n"
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
        "print the status table every S seconds, 0..86400 (0: only at the end and on SIGUSR1)",
        "0"},
       {"status-file", "FILE",
        "status table kept up to date here (default: "
        "$XDG_RUNTIME_DIR/tiller-launch-<name>.status, else in /tmp)",
        ""}}};
  spec.config_help = "the launch file (instead of the LAUNCH_FILE argument)";
  spec.arguments = "LAUNCH_FILE | status LAUNCH_FILE";
  spec.max_positional = 1;
  spec.takes_realtime = false;  // per process, in the launch file: children inherit SCHED_FIFO
  spec.commands = {{"status", 1}};
  const app::Args args = app::parse(argc, argv, spec);
  // Checked before anything starts.
  const double every =
      app::number_option(args, "status-every", 0, 86400, "a number of seconds from 0 to 86400");
  if (args.positional.size() == 2 && args.positional[0] == "status") {
    const LaunchFile lf = load_launch_file(args.positional[1]);
    const std::string f = status_file_of(args, lf.name);
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
  LaunchChoices c;
  c.groups = app::split_list(args.get("group"));
  c.only = app::split_list(args.get("only"));
  c.no_log = args.flag("no-log");
  c.log_dir = args.get("log-dir");
  c.log_file = args.get("log-file");
  if (args.explicitly("lcm-url")) c.lcm_url = with_default_ttl(args.lcm_url);
  Plan plan;
  try {
    plan = make_plan(load_launch_file(args.positional.empty() ? args.config : args.positional[0]),
                     c, now_stamp(), std::filesystem::current_path().string());
  } catch (const std::invalid_argument& e) {
    std::cerr << "tiller-launch: " << e.what() << "\n";
    return kExitUsage;
  }
  // Every child gets the LCM URL and the signing settings; the key is checked now, before
  // anything starts (docs/safety.md, "Who may command").
  std::map<std::string, std::string> child_env{{"LCM_DEFAULT_URL", plan.lf.lcm_url}};
  auth::Policy policy;  // the launcher's own: it checks heartbeats and signs its own
  try {
    if (args.explicitly("require-signed")) plan.lf.require_signed = true;
    const auto env = signing_env(plan.lf, {{"ROOT", plan.lf.root}},
                                 args.explicitly("key-file") ? args.auth.key_file : "", std::cout);
    child_env.insert(env.begin(), env.end());
    plan.signing = signing_summary(plan.lf, env);
    if (const auto k = env.find("TILLER_KEY_FILE"); k != env.end()) {
      policy.key = auth::load_key_file(k->second);
      policy.key_file = k->second;
    }
    policy.require_signed = plan.lf.require_signed;
    policy.window_us = from_seconds(plan.lf.auth_window_s);
  } catch (const std::exception& e) {
    std::cerr << "tiller-launch: " << e.what() << "\n";
    return kExitUsage;
  }
  const LaunchFile& lf = plan.lf;
  std::size_t width = 6;
  for (const auto& p : plan.procs) width = std::max(width, p.name.size());
  const RunDir run_dir(lf.name);  // ${RUN_DIR}: removed when the run ends
  const std::map<std::string, std::string> vars{{"LCM_URL", lf.lcm_url},
                                                {"ROOT", lf.root},
                                                {"LOG_FILE", plan.log_file},
                                                {"LAUNCH_NAME", lf.name},
                                                {"RUN_DIR", run_dir.path()}};
  PosixHost host(lf.root, vars, {self_dir()}, child_env, stdout, width);
  if (!check_programs(plan, host, std::cerr)) return kExitUsage;
  if (args.flag("check")) {
    print_check(std::cout, plan, host);
    return kExitOk;
  }
  if (plan.log && lf.logger.rotate > 0) {
    // One log per launch: last run's files move up one (launch/plan.hpp).
    const std::string problems = rotate_previous_logs(plan.log_file, lf.logger.rotate);
    if (!problems.empty()) std::cerr << "tiller-launch: " << problems;
  }
  return run_plan(plan, host, {every, status_file_of(args, lf.name), policy});
}

}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-launch", [&] { return run(argc, argv); });
}
