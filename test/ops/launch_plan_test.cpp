// tiller-launch's plan (launch/plan.hpp), without starting anything: which processes start and
// in what order, lcm-logger first with its command line, the log file's name (per run, fixed
// with rotate, a relative --log-file made absolute), the --lcm-url override, held-back
// processes, the replay manifest's content and the --check printout.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config.hpp"
#include "launch/plan.hpp"

namespace tiller::launch {
namespace {

LaunchFile parse(const std::string& text) {
  return load_launch(config::Value::parse(text, "run.yaml"), "/tmp");
}

const char* kRun = R"(name: run
root: .
lcm_url: udpm://239.255.76.67:7667?ttl=0
logger: {dir: logs, channels: "TILLER_.*"}
processes:
  - name: sim
    command: /bin/true
    args: [--config, config/sim/sim.yaml, --seed, "3"]
  - name: esc
    command: /bin/true
    args: ["--config=config/esc/x.yaml"]
    group: hw
  - name: mission
    command: /bin/true
    autostart: false
)";

TEST(LaunchPlan, LoggerFirstThenChosenProcessesAndTheHeldBackOnes) {
  const Plan p = make_plan(parse(kRun), {}, "2026-01-31-120000", "/home/u");
  ASSERT_EQ(p.procs.size(), 3u);
  EXPECT_EQ(p.procs[0].name, "logger");
  EXPECT_EQ(p.procs[0].command, "lcm-logger");
  EXPECT_EQ(p.procs[0].restart, Restart::kOnFailure);
  const std::vector<std::string> want{"--quiet", "--channel=TILLER_.*",
                                      "--lcm-url=udpm://239.255.76.67:7667?ttl=0",
                                      "/tmp/logs/2026-01-31-120000.lcmlog"};
  EXPECT_EQ(p.procs[0].args, want);
  EXPECT_EQ(p.procs[1].name, "sim");
  EXPECT_DOUBLE_EQ(p.procs[1].start_delay_s, 0.3);  // the logger subscribes first
  // ... and nothing starts before it has written: a late logger loses no operator START.
  EXPECT_EQ(p.procs[1].start_after_file, "/tmp/logs/2026-01-31-120000.lcmlog");
  EXPECT_TRUE(p.procs[2].start_after_file.empty());
  EXPECT_EQ(p.procs[2].name, "esc");
  EXPECT_EQ(p.log_file, "/tmp/logs/2026-01-31-120000.lcmlog");
  ASSERT_EQ(p.held_back.size(), 1u);
  EXPECT_EQ(p.held_back[0],
            "mission (autostart: false; start it with --group default or --only mission)");
}

TEST(LaunchPlan, ChoicesSelectRenameTheLogAndOverrideTheUrl) {
  LaunchChoices c;
  c.groups = {"hw"};
  c.log_file = "out/a.lcmlog";
  c.lcm_url = "udpm://239.255.76.68:7667?ttl=0";
  const Plan p = make_plan(parse(kRun), c, "stamp", "/home/u");
  ASSERT_EQ(p.procs.size(), 2u);
  EXPECT_EQ(p.procs[1].name, "esc");
  EXPECT_EQ(p.log_file, "/home/u/out/a.lcmlog");
  EXPECT_EQ(p.lf.lcm_url, "udpm://239.255.76.68:7667?ttl=0");
  EXPECT_EQ(p.procs[0].args[2], "--lcm-url=udpm://239.255.76.68:7667?ttl=0");
  // sim and mission are not started; only the autostart: false one is "held back".
  EXPECT_EQ(p.held_back.size(), 1u);

  c = {};
  c.no_log = true;
  c.only = {"mission"};
  const Plan q = make_plan(parse(kRun), c, "stamp", "/home/u");
  ASSERT_EQ(q.procs.size(), 1u);
  EXPECT_EQ(q.procs[0].name, "mission");
  EXPECT_FALSE(q.log);
  EXPECT_TRUE(q.held_back.empty());

  c = {};
  c.groups = {"nope"};
  EXPECT_THROW(make_plan(parse(kRun), c, "stamp", "/"), std::invalid_argument);
}

TEST(LaunchPlan, RotateFixesTheLogNameAndSplitAddsIncrement) {
  std::string text = kRun;
  text.replace(text.find("logger: {"), 9, "logger: {rotate: 3, split_mb: 5, ");
  Plan p = make_plan(parse(text), {}, "stamp", "/");
  EXPECT_EQ(p.log_file, "/tmp/logs/run.lcmlog");
  EXPECT_EQ(log_suffix(p.lf.logger), ".0");
  EXPECT_EQ(p.procs[1].start_after_file, "/tmp/logs/run.lcmlog.0");  // the file it writes
  EXPECT_EQ(p.procs[0].args[2], "--split-mb=5.000000");
  EXPECT_EQ(p.procs[0].args[3], "--rotate=3");
  text = kRun;
  text.replace(text.find("logger: {"), 9, "logger: {split_mb: 5, ");
  p = make_plan(parse(text), {}, "stamp", "/");
  EXPECT_EQ(p.procs[0].args[3], "--increment");
  EXPECT_EQ(log_suffix(p.lf.logger), ".00");
  EXPECT_EQ(log_stem("/a/b.lcmlog"), "/a/b");
  EXPECT_EQ(log_stem("/a/b.log"), "/a/b.log");
  EXPECT_EQ(default_status_file("run", ""), "/tmp/tiller-launch-run.status");
  EXPECT_EQ(default_status_file("run", "/run/user/1"), "/run/user/1/tiller-launch-run.status");
}

TEST(LaunchPlan, ManifestListsEachProcessWithItsConfigAndArgs) {
  const Plan p = make_plan(parse(kRun), {}, "stamp", "/");
  PosixHost host(p.lf.root, {}, {}, {}, stdout, 6);
  std::ostringstream m;
  write_manifest(m, p, host);
  const auto doc = config::Value::parse(m.str(), "manifest");
  EXPECT_EQ(doc.at("written_by").as_string(), "tiller-launch");
  EXPECT_EQ(doc.at("log").as_string(), "/tmp/logs/stamp.lcmlog");
  EXPECT_TRUE(doc.at("live").as_bool());
  EXPECT_DOUBLE_EQ(doc.at("live_match").as_number(), 0.85);
  const auto procs = doc.at("processes");
  EXPECT_EQ(procs.keys(), (std::vector<std::string>{"sim", "esc"}));  // no logger
  EXPECT_EQ(procs.at("sim").at("config").as_string(), "config/sim/sim.yaml");
  EXPECT_EQ(procs.at("esc").at("config").as_string(), "config/esc/x.yaml");
  EXPECT_EQ(procs.at("sim").at("args").items().size(), 4u);

  std::ostringstream check, err;
  EXPECT_TRUE(check_programs(p, host, err)) << err.str();
  print_check(check, p, host);
  EXPECT_NE(check.str().find("[default] sim: /bin/true --config config/sim/sim.yaml --seed 3"),
            std::string::npos)
      << check.str();
  EXPECT_NE(check.str().find("not started: mission"), std::string::npos);
}

TEST(LaunchPlan, MissingProgramIsNamedWithItsLine) {
  std::string text = kRun;
  text.replace(text.find("command: /bin/true"), 18, "command: tiller-no-such-program");
  const Plan p = make_plan(parse(text), {}, "stamp", "/");
  PosixHost host(p.lf.root, {}, {"/nonexistent"}, {}, stdout, 6);
  std::ostringstream err;
  EXPECT_FALSE(check_programs(p, host, err));
  EXPECT_NE(err.str().find("run.yaml:6: sim.command: expected a program next to tiller-launch or "
                           "on PATH, got \"tiller-no-such-program\""),
            std::string::npos)
      << err.str();
}

// Issue 33: a second launch with rotate reopened the last run's FILE.0 (lcm-logger --rotate
// rotates only when it splits). Before the logger starts, the previous files move up one.
TEST(LaunchPlan, RotatePreviousLogsStartsEachLaunchOnANewFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("rotate_test_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string file = (dir / "real-usv.lcmlog").string();
  const auto write = [](const std::string& f, const std::string& text) {
    std::ofstream(f) << text;
  };
  const auto read = [](const std::string& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(rotate_previous_logs(file, 3), "");  // first launch: nothing there
  write(file + ".0", "run 1");
  EXPECT_EQ(rotate_previous_logs(file, 3), "");
  EXPECT_FALSE(fs::exists(file + ".0"));
  EXPECT_EQ(read(file + ".1"), "run 1");
  write(file + ".0", "run 2");
  rotate_previous_logs(file, 3);
  write(file + ".0", "run 3");
  rotate_previous_logs(file, 3);  // run 1 was the oldest of 3: gone
  EXPECT_FALSE(fs::exists(file + ".0"));
  EXPECT_EQ(read(file + ".1"), "run 3");
  EXPECT_EQ(read(file + ".2"), "run 2");
  EXPECT_FALSE(fs::exists(file + ".3"));
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tiller::launch
