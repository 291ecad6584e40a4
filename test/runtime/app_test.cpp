// The common command line (runtime/app.hpp): default configs are found in the source tree from
// any directory; standard options a program does not take are refused (exit 2, a message
// naming the option) instead of ignored; FILE option defaults are resolved like --config.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "runtime/app.hpp"

namespace tiller::app {
namespace {

namespace fs = std::filesystem;

// Runs parse() on a command line.
Args run(const Spec& spec, std::vector<std::string> words) {
  words.insert(words.begin(), spec.program);
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  return parse(static_cast<int>(argv.size()), argv.data(), spec);
}

// Changes to an empty temporary directory for the test's lifetime.
struct ElsewhereDir {
  fs::path old = fs::current_path();
  fs::path dir = fs::temp_directory_path() / ("tiller-app-test-" + std::to_string(getpid()));
  ElsewhereDir() {
    fs::create_directories(dir);
    fs::current_path(dir);
  }
  ~ElsewhereDir() {
    fs::current_path(old);
    fs::remove_all(dir);
  }
};

TEST(App, DefaultConfigIsFoundFromAnotherDirectory) {
  ElsewhereDir here;
  const Spec spec{"tiller-x", "test", "config/control/otter.yaml", {}};
  const Args a = run(spec, {});
  EXPECT_EQ(a.config, std::string(TILLER_SOURCE_DIR) + "/config/control/otter.yaml");
  EXPECT_TRUE(fs::exists(a.config));
  // Relative to config/ as well (tiller-sim's default is "sim/sim.yaml").
  EXPECT_EQ(run({"tiller-x", "test", "sim/sim.yaml", {}}, {}).config,
            std::string(TILLER_SOURCE_DIR) + "/config/sim/sim.yaml");
  // An explicit one too.
  EXPECT_EQ(run(spec, {"--config", "config/mixer/otter.yaml"}).config,
            std::string(TILLER_SOURCE_DIR) + "/config/mixer/otter.yaml");
  // A file that exists here wins over the source tree.
  fs::create_directories("config/control");
  { std::ofstream("config/control/otter.yaml") << "x: 1\n"; }
  EXPECT_EQ(run(spec, {}).config, "config/control/otter.yaml");
  // Absolute and missing paths are left alone (the loader then names them).
  EXPECT_EQ(run(spec, {"--config", "/nonexistent/a.yaml"}).config, "/nonexistent/a.yaml");
  EXPECT_EQ(run(spec, {"--config", "nowhere.yaml"}).config, "nowhere.yaml");
}

TEST(App, FileOptionDefaultsAreResolved) {
  ElsewhereDir here;
  const Spec spec{"tiller-x",
                  "test",
                  "",
                  {{"mission", "FILE", "mission", "config/missions/default.yaml"},
                   {"name", "TEXT", "not a file", "config/missions/default.yaml"}}};
  const Args a = run(spec, {});
  EXPECT_EQ(a.get("mission"), std::string(TILLER_SOURCE_DIR) + "/config/missions/default.yaml");
  EXPECT_EQ(a.get("name"), "config/missions/default.yaml");
  EXPECT_EQ(run(spec, {"--mission", "mine.yaml"}).get("mission"), "mine.yaml");
}

TEST(App, UnusedStandardOptionsAreRefused) {
  const Spec no_config{"tiller-plot", "test", "", {}, false, true};
  EXPECT_EXIT(run(no_config, {"--config", "a.yaml"}), ::testing::ExitedWithCode(2),
              "tiller-plot: --config is not taken: tiller-plot has no config file");
  const Spec no_lcm{"tiller-plot", "test", "", {}, true, false};
  EXPECT_EXIT(run(no_lcm, {"--lcm-url=udpm://239.255.76.67:7667"}), ::testing::ExitedWithCode(2),
              "tiller-plot: --lcm-url is not taken: tiller-plot opens no LCM");
  // Taken ones still work.
  EXPECT_EQ(run(no_lcm, {"--config", "/a.yaml"}).config, "/a.yaml");
  EXPECT_EQ(run(no_config, {"--lcm-url", "memq://"}).lcm_url, "memq://");
}

// --help (on stdout; the death test reads stderr, so one is sent to the other): one usage line
// with the positional arguments, only the options taken, each default once.
TEST(App, HelpListsOnlyTheOptionsTakenWithEachDefaultOnce) {
  Spec spec{"tiller-plot", "draws", "", {{"output", "FILE", "PNG to write", "a.png"}},
            false,         false};
  spec.arguments = "LOG";
  spec.max_positional = 1;
  auto help = [&](const char* regex) {
    EXPECT_EXIT(
        {
          dup2(2, 1);
          run(spec, {"--help"});
        },
        ::testing::ExitedWithCode(0), regex);
  };
  help(
      "^Usage: tiller-plot \\[options\\] LOG\ndraws\n\nOptions:\n  --help +show this help and "
      "exit\n  --output FILE +PNG to write \\(default: a.png\\)\n$");
  spec.takes_config = true;
  spec.default_config = "plot.yaml";
  help("  --config FILE +YAML config \\(default: plot.yaml\\)\n  --output");
}

// A positional argument a program does not take is refused (exit 2), naming it.
TEST(App, UnexpectedPositionalArgumentsAreRefusedNamingThem) {
  const Spec none{"tiller-mixer", "mixes", "", {{"describe", "", "describe", ""}}, true, true};
  EXPECT_EXIT(run(none, {"config/mixer/seed000_rov4.yaml", "--describe"}),
              ::testing::ExitedWithCode(2),
              "tiller-mixer: unexpected argument 'config/mixer/seed000_rov4.yaml' \\(tiller-mixer "
              "takes no positional arguments\\)");
  Spec one = none;
  one.arguments = "LOG";
  one.max_positional = 1;
  EXPECT_EQ(run(one, {"a.lcmlog"}).positional, std::vector<std::string>{"a.lcmlog"});
  EXPECT_EXIT(run(one, {"a.lcmlog", "b.lcmlog"}), ::testing::ExitedWithCode(2),
              "unexpected argument 'b.lcmlog' \\(tiller-mixer takes LOG\\)");
  Spec cmds = none;
  cmds.commands = {{"summary", 1}, {"wait", 3}};
  EXPECT_EQ(run(cmds, {"wait", "C", "F", "V"}).positional.size(), 4u);
  EXPECT_EXIT(run(cmds, {"summary", "a", "b"}), ::testing::ExitedWithCode(2),
              "unexpected argument 'b'");
  EXPECT_EXIT(run(cmds, {"sumary", "a"}), ::testing::ExitedWithCode(2),
              "unexpected argument 'sumary' \\(commands: summary, wait\\)");
}

// Numeric options: the whole string, finite, within range; the error names the option, what was
// expected and the value.
TEST(App, NumberAndIntegerOptionsAreCheckedWhole) {
  Args a;
  auto msg = [&](const std::function<void()>& f) {
    try {
      f();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto num = [&](const std::string& v) {
    a.values["x"] = v;
    return msg([&] { (void)number_option(a, "x", -1, 2, "a number in [-1, 2]"); });
  };
  a.values["x"] = "1.5";
  EXPECT_EQ(number_option(a, "x", -1, 2, "e"), 1.5);
  a.values["x"] = "-1e0";
  EXPECT_EQ(number_option(a, "x", -1, 2, "e"), -1.0);
  EXPECT_EQ(num("abc"), "--x: expected a number in [-1, 2], got 'abc'");
  for (const char* bad : {"", "1x", " 1", "1 ", "inf", "nan", "2.5", "-1.01", "0x1"})
    EXPECT_EQ(num(bad), std::string("--x: expected a number in [-1, 2], got '") + bad + "'") << bad;
  auto integer = [&](const std::string& v) {
    a.values["n"] = v;
    return msg([&] { (void)integer_option(a, "n", 0, 10, "a whole number in [0, 10]"); });
  };
  a.values["n"] = "7";
  EXPECT_EQ(integer_option(a, "n", 0, 10, "e"), 7);
  for (const char* bad : {"", "1.0", "-1", "11", "3x", "99999999999999999999"})
    EXPECT_EQ(integer(bad),
              std::string("--n: expected a whole number in [0, 10], got '") + bad + "'")
        << bad;
}

// The helpers tiller-launch and tiller-replay each had a copy of.
TEST(App, SplitListAndExplicitlyGivenOptions) {
  EXPECT_EQ(split_list("a,b,,c,"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(split_list("").empty());
  const Spec spec{"tiller-x", "test", "", {{"n", "N", "a number", "1"}}, true, true};
  const Args a = run(spec, {"--n=2", "--lcm-url", "memq://"});
  EXPECT_TRUE(a.explicitly("n"));
  EXPECT_TRUE(a.explicitly("lcm-url"));
  EXPECT_FALSE(a.explicitly("config"));
  EXPECT_FALSE(run(spec, {}).explicitly("n"));  // its default is not "given"
  EXPECT_EQ(run(spec, {}).get("n"), "1");
}

}  // namespace
}  // namespace tiller::app
