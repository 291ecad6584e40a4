// tiller-replay's plan (replaytool/plan.hpp): without a manifest, the replayable processes whose
// heartbeat is in the log (the others reported as skipped, with why); with one, its processes,
// root and tolerances (the command line's win); --config needs one --process; a process whose
// config is the vehicle's is skipped (all) or refused (one); recorded path arguments resolve
// against the manifest's root.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "replaytool/plan.hpp"
#include "runtime/heartbeat_name.hpp"

namespace tiller::replaytool {
namespace {

namespace fs = std::filesystem;

std::vector<Event> heartbeats_of(const std::vector<std::string>& names) {
  std::vector<Event> log;
  for (const auto& n : names) log.push_back(Event{heartbeat_channel_of(n), 1000, {}});
  return log;
}

std::vector<std::string> names_of(const ReplayPlan& p) {
  std::vector<std::string> out;
  for (const auto& q : p.processes) out.push_back(q.entry->name);
  return out;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no error)";
}

struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("tiller-replay-plan-" + std::to_string(getpid()));
  TempDir() { fs::create_directories(dir); }
  ~TempDir() { fs::remove_all(dir); }
};

TEST(ReplayPlan, WithoutManifestTheReplayableProcessesThatRan) {
  ReplayRequest req;
  req.log_path = "/nonexistent/run.lcmlog";
  ReplayPlan plan = plan_from_manifest(req);
  EXPECT_TRUE(plan.manifest.empty());
  plan_from_log(plan, req, heartbeats_of({"path-follower", "mixer", "mission", "sim"}));
  // mixer ran but its config is the vehicle's: skipped; mission is not replayable.
  EXPECT_EQ(names_of(plan), (std::vector<std::string>{"path-follower", "sim"}));
  ASSERT_EQ(plan.skipped.size(), 2u);
  EXPECT_EQ(plan.skipped[0], "mission (its heartbeat is in the log: not a replayable process)");
  EXPECT_EQ(plan.skipped[1],
            "mixer (needs its vehicle's config: a manifest or --process mixer --config FILE)");
  EXPECT_EQ(plan.tol.time_us, 0);
}

TEST(ReplayPlan, OneProcessAndConfigChecks) {
  ReplayRequest req;
  req.log_path = "/nonexistent/run.lcmlog";
  req.process = "nope";
  EXPECT_EQ(error_of([&] { plan_from_manifest(req); })
                .rfind("--process: no replayable process "
                       "named \"nope\" (replayable: mixer, ",
                       0),
            0u);
  req.process = "all";
  req.config = "x.yaml";
  ReplayPlan plan = plan_from_manifest(req);
  EXPECT_EQ(error_of([&] { plan_from_log(plan, req, {}); }), "--config needs --process NAME");
  req.process = "mixer";
  req.config.reset();
  plan = plan_from_manifest(req);
  EXPECT_EQ(error_of([&] { plan_from_log(plan, req, {}); }),
            "mixer has no default config (it is the vehicle's): give --config FILE or a manifest "
            "(--configs)");
  req.config = "config/mixer/otter.yaml";
  plan = plan_from_manifest(req);
  plan_from_log(plan, req, {});  // one process: replayed even when its heartbeat is absent
  ASSERT_EQ(names_of(plan), (std::vector<std::string>{"mixer"}));
  EXPECT_EQ(plan.processes[0].config, "config/mixer/otter.yaml");
}

TEST(ReplayPlan, ManifestGivesProcessesRootAndTolerancesAndTheCommandLineWins) {
  TempDir t;
  const std::string log = (t.dir / "run.lcmlog").string();
  std::ofstream(t.dir / "run.replay.yaml") << "root: " << t.dir.string() << "\n"
                                           << "live: true\n"
                                           << "tolerance: 0.01\n"
                                           << "relative_tolerance: 0.02\n"
                                           << "live_match: 0.85\n"
                                           << "processes:\n"
                                           << "  boat: {program: /x/tiller-sim, config: s.yaml,"
                                           << " args: [--vehicle, config/v.yaml, --seed, '2']}\n"
                                           << "  done: {program: tiller-log, args: [wait]}\n"
                                           << "  mixer: m.yaml\n";
  ReplayRequest req;
  req.log_path = log;
  req.tolerance = 0.5;
  ReplayPlan plan = plan_from_manifest(req);
  EXPECT_EQ(plan.manifest, (t.dir / "run.replay.yaml").string());
  EXPECT_TRUE(plan.from_manifest);
  EXPECT_TRUE(plan.live);
  EXPECT_DOUBLE_EQ(plan.tol.abs, 0.5);  // the command line's
  EXPECT_DOUBLE_EQ(plan.tol.rel, 0.02);
  EXPECT_DOUBLE_EQ(plan.tol.live_match, 0.85);
  EXPECT_EQ(plan.tol.time_us, 20'000);  // a live log without a time tolerance: 20 ms
  plan_from_log(plan, req, {});
  EXPECT_EQ(names_of(plan), (std::vector<std::string>{"sim", "mixer"}));
  EXPECT_EQ(plan.skipped,
            (std::vector<std::string>{"done (tiller-log: not a replayable process)"}));
  EXPECT_EQ(
      plan.processes[0].args,
      (std::vector<std::string>{"--vehicle", (t.dir / "config/v.yaml").string(), "--seed", "2"}));
  EXPECT_EQ(plan.resolve(plan.processes[1].config), (t.dir / "m.yaml").string());

  std::ofstream(t.dir / "bad.yaml") << "processes:\n  teapot: t.yaml\n";
  req.manifest = (t.dir / "bad.yaml").string();
  EXPECT_NE(error_of([&] { plan_from_manifest(req); }).find("not \"teapot\""), std::string::npos);
}

TEST(ReplayPlan, NothingToReplayIsAnErrorAfterTheSkippedAreListed) {
  ReplayRequest req;
  req.log_path = "/nonexistent/run.lcmlog";
  ReplayPlan plan = plan_from_manifest(req);
  plan_from_log(plan, req, heartbeats_of({"mission"}));
  std::ostringstream out;
  EXPECT_EQ(error_of([&] { run_plan(plan, {}, 1, out); }),
            "no replayable process ran in /nonexistent/run.lcmlog (see --list)");
  EXPECT_EQ(out.str(),
            "skipped: mission (its heartbeat is in the log: not a replayable process)\n");
}

}  // namespace
}  // namespace tiller::replaytool
