// Real time (runtime/realtime.hpp) with a fake system: what is asked for, what is called, and the
// message of each refusal (what is missing, how to grant it); and the launch file's realtime:
// entry becoming the program's flags. The real kernel's answers are realtime_live_test's.
#include <gtest/gtest.h>

#include <cerrno>
#include <string>
#include <vector>

#include "core/config.hpp"
#include "launch/launch_file.hpp"
#include "runtime/realtime.hpp"

namespace tiller::realtime {
namespace {

struct FakeSystem : System {
  Limits l;
  int fifo_errno = 0, lock_errno = 0;
  std::vector<std::string> calls;
  Limits limits() override { return l; }
  int set_fifo(int priority) override {
    calls.push_back("fifo " + std::to_string(priority));
    return fifo_errno;
  }
  int lock_all() override {
    calls.push_back("mlockall");
    return lock_errno;
  }
};

Request both(int priority) {
  Request r;
  r.priority = priority;
  r.lock_memory = true;
  return r;
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(Realtime, NothingAskedNothingCalled) {
  FakeSystem sys;
  const Report rep = apply(Request{}, sys);
  EXPECT_TRUE(sys.calls.empty());
  EXPECT_TRUE(rep.granted());
  EXPECT_EQ(rep.priority, 0);
}

TEST(Realtime, RootGetsBothLockFirst) {
  FakeSystem sys;
  sys.l.cap_sys_nice = sys.l.cap_ipc_lock = true;
  const Report rep = apply(both(45), sys);
  EXPECT_EQ(sys.calls, (std::vector<std::string>{"mlockall", "fifo 45"}));
  EXPECT_TRUE(rep.granted());
  EXPECT_EQ(rep.priority, 45);
  EXPECT_TRUE(rep.locked);
  EXPECT_EQ(summary(rep), "SCHED_FIFO priority 45, memory locked");
}

TEST(Realtime, RlimitsAloneAreEnough) {  // systemd LimitRTPRIO=49 LimitMEMLOCK=infinity
  FakeSystem sys;
  sys.l.rtprio = 49;
  sys.l.memlock = Limits::kInfinity;
  const Report rep = apply(both(45), sys);
  EXPECT_EQ(sys.calls.size(), 2u);
  EXPECT_TRUE(rep.granted());
}

TEST(Realtime, FifoRefusedNamesTheMissingLimitAndHowToGrantIt) {
  FakeSystem sys;
  sys.l.rtprio = 10;  // below 45
  sys.fifo_errno = EPERM;
  Request r;
  r.priority = 45;
  const Report rep = apply(r, sys);
  ASSERT_EQ(rep.problems.size(), 1u);
  const std::string& m = rep.problems[0];
  EXPECT_TRUE(has(m, "SCHED_FIFO priority 45 refused (EPERM)")) << m;
  EXPECT_TRUE(has(m, "CAP_SYS_NICE or RLIMIT_RTPRIO >= 45")) << m;
  EXPECT_TRUE(has(m, "RLIMIT_RTPRIO 10")) << m;
  EXPECT_TRUE(has(m, "LimitRTPRIO=45")) << m;
  EXPECT_TRUE(has(m, "rtprio 45")) << m;  // limits.conf
  EXPECT_FALSE(has(m, "user namespace")) << m;
  EXPECT_EQ(rep.priority, 0);
  EXPECT_EQ(summary(rep), "normal scheduler, memory not locked");
}

TEST(Realtime, UserNamespaceRootHasNoHostCapabilitiesAndIsToldSo) {  // tools/netns-run
  FakeSystem sys;
  sys.l.cap_sys_nice = sys.l.cap_ipc_lock = true;  // what CapEff says inside the namespace
  sys.l.user_namespace = true;
  sys.l.memlock = 8 << 20;
  sys.fifo_errno = EPERM;
  const Report rep = apply(both(45), sys);
  // mlockall is not tried: the capability does not count and the limit is finite.
  EXPECT_EQ(sys.calls, (std::vector<std::string>{"fifo 45"}));
  ASSERT_EQ(rep.problems.size(), 2u);
  EXPECT_TRUE(has(rep.problems[0], "memory not locked")) << rep.problems[0];
  EXPECT_TRUE(has(rep.problems[0], "RLIMIT_MEMLOCK 8 MiB")) << rep.problems[0];
  EXPECT_TRUE(has(rep.problems[0], "LimitMEMLOCK=infinity")) << rep.problems[0];
  for (const auto& m : rep.problems) {
    EXPECT_TRUE(has(m, "user namespace")) << m;
    EXPECT_TRUE(has(m, "unshare -n without -r")) << m;
  }
  EXPECT_TRUE(has(rep.problems[1], "SCHED_FIFO priority 45 refused (EPERM)")) << rep.problems[1];
  EXPECT_FALSE(rep.locked);
}

TEST(Realtime, FiniteMemlockIsNotTriedEvenWhenLargeEnoughForNow) {
  FakeSystem sys;
  sys.l.memlock = 64ULL << 30;  // 64 GiB: still finite (MCL_FUTURE would fail past it)
  Request r;
  r.lock_memory = true;
  const Report rep = apply(r, sys);
  EXPECT_TRUE(sys.calls.empty());
  ASSERT_EQ(rep.problems.size(), 1u);
  EXPECT_TRUE(has(rep.problems[0], "RLIMIT_MEMLOCK 65536 MiB")) << rep.problems[0];
  EXPECT_TRUE(has(rep.problems[0], "memlock unlimited")) << rep.problems[0];
}

TEST(Realtime, MlockallFailureIsReportedWithItsErrno) {
  FakeSystem sys;
  sys.l.cap_ipc_lock = true;
  sys.lock_errno = ENOMEM;
  Request r;
  r.lock_memory = true;
  const Report rep = apply(r, sys);
  ASSERT_EQ(rep.problems.size(), 1u);
  EXPECT_TRUE(has(rep.problems[0], "mlockall refused (ENOMEM)")) << rep.problems[0];
  EXPECT_TRUE(has(rep.problems[0], "CAP_IPC_LOCK held")) << rep.problems[0];
}

TEST(Realtime, RefusedDespiteTheLimitPointsAtTheCgroup) {
  FakeSystem sys;
  sys.l.rtprio = 99;
  sys.fifo_errno = EPERM;
  Request r;
  r.priority = 45;
  const Report rep = apply(r, sys);
  ASSERT_EQ(rep.problems.size(), 1u);
  EXPECT_TRUE(has(rep.problems[0], "RLIMIT_RTPRIO is 99")) << rep.problems[0];
  EXPECT_TRUE(has(rep.problems[0], "cpu.rt_runtime_us")) << rep.problems[0];
}

}  // namespace
}  // namespace tiller::realtime

namespace tiller::launch {
namespace {

LaunchFile parse(const std::string& processes) {
  return load_launch(config::Value::parse("name: rt\nroot: .\nprocesses:\n" + processes, "rt.yaml"),
                     "/tmp");
}

std::string error_of(const std::string& processes) {
  try {
    parse(processes);
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(LaunchRealtime, EntryBecomesTheProgramsFlagsAfterItsArgs) {
  const LaunchFile lf = parse(
      "  - {name: esc, command: tiller-esc, args: [--config, x.yaml],"
      " realtime: {priority: 45, required: true}}\n"
      "  - {name: mixer, command: build/bin/tiller-mixer, realtime: {priority: 40,"
      " lock_memory: false}}\n"
      "  - {name: sim, command: tiller-sim}\n");
  ASSERT_EQ(lf.processes.size(), 3u);
  const auto& esc = lf.processes[0];
  EXPECT_EQ(esc.realtime.priority, 45);
  EXPECT_TRUE(esc.realtime.lock_memory);  // the default with a realtime: entry
  EXPECT_TRUE(esc.realtime.required);
  EXPECT_EQ(esc.args, (std::vector<std::string>{"--config", "x.yaml", "--realtime-priority=45",
                                                "--lock-memory", "--realtime-required"}));
  EXPECT_EQ(lf.processes[1].args, (std::vector<std::string>{"--realtime-priority=40"}));
  EXPECT_TRUE(lf.processes[2].args.empty());
  EXPECT_FALSE(lf.processes[2].realtime.any());
}

TEST(LaunchRealtime, BadEntriesAreRefusedWithLineAndKey) {
  EXPECT_NE(error_of("  - {name: esc, command: tiller-esc, realtime: {priority: 100}}\n")
                .find("realtime.priority"),
            std::string::npos);
  EXPECT_NE(error_of("  - {name: esc, command: tiller-esc, realtime: {priority: 0}}\n")
                .find("realtime.priority"),
            std::string::npos);
  EXPECT_NE(error_of("  - {name: esc, command: tiller-esc, realtime: {priorty: 40}}\n")
                .find("realtime.priorty: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("  - {name: esc, command: tiller-esc, realtime: {lock_memory: false}}\n")
                .find("nothing to apply"),
            std::string::npos);
  const std::string other =
      error_of("  - {name: log, command: lcm-logger, realtime: {priority: 40}}\n");
  EXPECT_NE(other.find("rt.yaml:4: processes[0].command: expected a tiller-* program with "
                       "realtime:"),
            std::string::npos)
      << other;
  EXPECT_NE(error_of("  - {name: esc, command: tiller-esc, realtime: 40}\n").find("a map"),
            std::string::npos);
}

}  // namespace
}  // namespace tiller::launch
