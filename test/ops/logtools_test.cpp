// Log tools: the .lcm parser gives the same fingerprint lcm-gen gave every type; generic
// decoding matches the generated decoders field by field; the summary counts, rates, gaps and
// heartbeat counters of a hand-built log; CSV export selects fields and handles variable arrays.
#include <gtest/gtest.h>

#include <sstream>

#include <tiller/heartbeat_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/thruster_command_t.hpp>

#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "logtools/csv.hpp"
#include "logtools/lcm_schema.hpp"
#include "logtools/log_io.hpp"
#include "logtools/logsummary.hpp"
#include "runtime/log.hpp"

namespace tiller::logtools {
namespace {

TEST(LcmSchema, FingerprintOfEveryParsedTypeMatchesLcmGen) {
  const TypeDb& db = tiller_types();
  std::map<std::string, StructDef> all;
  for (const auto& n : db.names()) all[n] = *db.by_name(n);
  ASSERT_GE(all.size(), 22u);
  for (const auto& [name, def] : all) EXPECT_EQ(lcm_fingerprint(def, all), def.hash) << name;
}

TEST(LcmSchema, ParserReportsLineOfBadSyntax) {
  try {
    parse_lcm("package p;\nstruct a_t {\n  double x\n  int8_t y;\n}\n", "a_t.lcm");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "a_t.lcm:4: expected ';' after field x, got 'int8_t'");
  }
}

template <class Msg>
Event ev(const std::string& ch, TimeUs t, const Msg& m) {
  return encode(ch, t, m);
}

TEST(LcmSchema, DecodesNestedAndVariableArrays) {
  path_t p{};
  p.utime = 42;
  p.path_id = -7;
  p.n_waypoints = 2;
  p.waypoints.resize(2);
  p.waypoints[1].position[2] = -1.25;
  p.waypoints[1].has_heading = true;
  p.waypoints[1].heading = 0.5;
  const Event e = ev("TILLER_PATH", 1, p);
  Decoded d;
  ASSERT_TRUE(tiller_types().decode(e.data.data(), e.data.size(), d));
  EXPECT_EQ(d.type->name, "path_t");
  EXPECT_EQ(d.number("utime"), 42);
  EXPECT_EQ(d.number("path_id"), -7);
  EXPECT_EQ(d.number("waypoints[1].position[2]"), -1.25);
  EXPECT_EQ(d.number("waypoints[1].has_heading"), 1);
  EXPECT_EQ(d.number("waypoints[1].heading"), 0.5);
  EXPECT_EQ(d.fields.size(), 3u + 2u * 5u);
  // Truncated bytes are refused.
  EXPECT_FALSE(tiller_types().decode(e.data.data(), e.data.size() - 1, d));
}

TEST(LogSummary, CountsRatesGapsAndHeartbeatCounters) {
  std::vector<Event> log;
  odometry_t o{};
  for (int k = 0; k <= 100; ++k) {
    if (k >= 40 && k < 50) continue;  // a 0.55 s hole at 20 Hz
    log.push_back(ev("TILLER_ODOMETRY", 1'000'000 + k * 50'000, o));
  }
  heartbeat_t hb{};
  hb.process = "mixer";
  hb.received = 100;
  hb.rejected = 3;
  hb.n_counters = 2;
  hb.counter_names = {"rejected.wrench.nan", "stale.arm"};
  hb.counter_values = {3, 0};
  log.push_back(ev("TILLER_HEARTBEAT_MIXER", 2'000'000, hb));
  std::sort(log.begin(), log.end(), [](const Event& a, const Event& b) { return a.time < b.time; });
  const LogSummary s = summarize(log);
  ASSERT_EQ(s.channels.size(), 2u);
  const ChannelStats& od = s.channels[1];
  EXPECT_EQ(od.channel, "TILLER_ODOMETRY");
  EXPECT_EQ(od.type, "odometry_t");
  EXPECT_EQ(od.count, 91);
  EXPECT_NEAR(od.rate_hz, 90.0 / 5.0, 1e-9);
  EXPECT_EQ(od.median_period, 50'000);
  EXPECT_EQ(od.max_gap, 550'000);
  EXPECT_EQ(od.max_gap_at, 1'000'000 + 39 * 50'000);
  EXPECT_EQ(od.gaps, 1);
  ASSERT_EQ(s.processes.size(), 1u);
  EXPECT_EQ(s.processes[0].rejected, 3);
  EXPECT_EQ(s.processes[0].counters.size(), 1u);  // zero counters left out
  EXPECT_EQ(s.processes[0].counters.at("rejected.wrench.nan"), 3);
  const std::string text = format_summary(s);
  EXPECT_NE(text.find("rejected.wrench.nan = 3"), std::string::npos) << text;
}

TEST(Csv, SelectsFieldsByPrefixAndUnitesVariableArrays) {
  std::vector<Event> log;
  thruster_command_t c{};
  c.n_thrusters = 1;
  c.names = {"port"};
  c.command = {0.5};
  log.push_back(ev("TILLER_THRUSTER_COMMAND", 1'000'000, c));
  c.n_thrusters = 2;
  c.names = {"port", "stbd,x"};
  c.command = {-0.25, 1.0};
  log.push_back(ev("TILLER_THRUSTER_COMMAND", 1'500'000, c));
  std::ostringstream os;
  EXPECT_EQ(write_csv(os, log, "TILLER_THRUSTER_COMMAND", {"command", "names"}, 1'000'000), 2u);
  EXPECT_EQ(os.str(),
            "t_s,names[0],command[0],names[1],command[1]\n"
            "0.000000,port,0.5,,\n"
            "0.500000,port,-0.25,\"stbd,x\",1\n");
  EXPECT_TRUE(field_selected("waypoints[3].heading", {"waypoints"}));
  EXPECT_FALSE(field_selected("waypoints_x", {"waypoints"}));
}

// A file that is not an LCM log is named as such (lcm::LogFile would read it as 0 events).
TEST(LogIo, NotAnLcmLogIsSaidSo) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tiller-logio-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "text.lcmlog") << "hello, not a log\n";
  std::ofstream(dir / "empty.lcmlog");
  auto message = [](const fs::path& p) {
    try {
      read_any_log(p.string());
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message(dir / "text.lcmlog").find("not an LCM log"), std::string::npos);
  EXPECT_NE(message(dir / "empty.lcmlog").find("empty (0 bytes)"), std::string::npos);
  fs::remove_all(dir);
}

// tiller-log csv --fields with a name the channel does not have: exit 2, listing its fields.
TEST(LogTool, UnknownFieldFailsAndListsTheFields) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tiller-logcsv-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    LogWriter w((dir / "run.lcmlog").string());
    thruster_command_t c{};
    c.n_thrusters = 1;
    c.names = {"port"};
    c.command = {0.5};
    const auto e = ev("TILLER_THRUSTER_COMMAND", 1'000'000, c);
    w.write(e.channel, e.data.data(), static_cast<int>(e.data.size()), e.time);
  }
  const std::string err = (dir / "err.txt").string();
  const std::string base = std::string(TILLER_BIN_DIR) + "/tiller-log csv " +
                           (dir / "run.lcmlog").string() + " TILLER_THRUSTER_COMMAND --fields ";
  const int rc = std::system((base + "command,nosuch > /dev/null 2> " + err).c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::stringstream ss;
  ss << std::ifstream(err).rdbuf();
  EXPECT_NE(ss.str().find("no field \"nosuch\" in TILLER_THRUSTER_COMMAND (thruster_command_t); "
                          "its fields: utime,"),
            std::string::npos)
      << ss.str();
  EXPECT_NE(ss.str().find("command[0]"), std::string::npos) << ss.str();
  EXPECT_EQ(std::system((base + "command > /dev/null 2>&1").c_str()), 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace tiller::logtools
