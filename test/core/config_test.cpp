// Strict config loader: every error kind names the file, the line, the key path and what was
// expected; valid documents load into values; unknown keys are caught anywhere in the tree.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "core/angles.hpp"
#include "core/config.hpp"

namespace tiller::config {
namespace {

const char* kDoc = R"(name: otter
rate_hz: 50
enabled: true
heading_deg: 90
limits:
  max: 1.5
  names: [a, b]
thrusters:
  - name: port
    position: [0.0, -0.395, 0.0]
  - name: starboard
    position: [0.0, 0.395, 0.0]
)";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Config, ReadsTypedValues) {
  const Value v = Value::parse(kDoc, "test.yaml");
  EXPECT_EQ(v.string("name"), "otter");
  EXPECT_EQ(v.integer("rate_hz", 1, 1000), 50);
  EXPECT_TRUE(v.boolean("enabled"));
  EXPECT_DOUBLE_EQ(v.angle_deg("heading_deg"), kPi / 2);
  EXPECT_DOUBLE_EQ(v.at("limits").number("max", {0, 2}), 1.5);
  const auto t = v.at("thrusters").items();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[1].numbers("position", 3), (std::vector<double>{0.0, 0.395, 0.0}));
  EXPECT_DOUBLE_EQ(v.number_or("absent", 7.0), 7.0);
}

// Value::set (tiller-run --set): replaces a value in the loaded document before a loader reads
// it, adds a missing last key (for check_all_used to judge), and refuses a path it cannot follow.
TEST(Config, SetReplacesAValueBeforeItIsRead) {
  const Value v = Value::parse(kDoc, "test.yaml");
  v.set("limits.max", "2.5");
  v.set("rate_hz", "[1, 2]");
  v.set("limits.min", "0.5");  // absent: added
  EXPECT_DOUBLE_EQ(v.at("limits").number("max"), 2.5);
  EXPECT_DOUBLE_EQ(v.at("limits").number("min"), 0.5);
  EXPECT_EQ(v.at("rate_hz").as_numbers(2), (std::vector<double>{1, 2}));
  EXPECT_EQ(v.string("name"), "otter");  // the rest untouched
  v.set("name", "fast");
  EXPECT_DOUBLE_EQ(v.at("limits").number("max"), 2.5);
  EXPECT_EQ(v.string("name"), "fast");
  // Set but never read: the strict check still names it.
  const Value w = Value::parse(kDoc, "test.yaml");
  w.mark_used();
  w.set("limits.maxx", "3");
  EXPECT_NE(error_of([&] { w.check_all_used(); }).find("limits.maxx: unknown key"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { v.set("nothing.max", "1"); }),
            "test.yaml: nothing.max: cannot set: no key nothing in the file");
  EXPECT_EQ(error_of([&] { v.set("rate_hz.x", "1"); }),
            "test.yaml: rate_hz.x: cannot set: rate_hz is not a map of keys");
  EXPECT_EQ(error_of([&] { v.set("limits..max", "1"); }),
            "test.yaml: limits..max: expected a key path like a.b.c");
  EXPECT_EQ(error_of([&] { v.set("limits.max", ""); }),
            "test.yaml: limits.max: expected a value after '=', got nothing");
  EXPECT_NE(error_of([&] { v.set("limits.max", "[1, 2"); }).find("YAML syntax error"),
            std::string::npos);
}

TEST(Config, MissingKeyNamesFileLineAndPath) {
  const Value v = Value::parse(kDoc, "vehicle.yaml");
  EXPECT_EQ(error_of([&] { v.at("limits").at("min"); }),
            "vehicle.yaml:6: limits.min: missing required key");
}

TEST(Config, MissingKeySaysWhatWasExpected) {
  const Value v = Value::parse(kDoc, "vehicle.yaml");
  const Value limits = v.at("limits");
  struct Case {
    std::function<void()> read;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[&] {
         limits.number("min", {0, 1});
       },
       "vehicle.yaml:6: limits.min: missing required key (expected a number in [0, 1])"},
      {[&] { limits.number("min"); },
       "vehicle.yaml:6: limits.min: missing required key (expected a number)"},
      {[&] { limits.number("min", Range::at_least(0.5)); },
       "vehicle.yaml:6: limits.min: missing required key (expected a number >= 0.5)"},
      {[&] { limits.number("min", Range::positive()); },
       "vehicle.yaml:6: limits.min: missing required key (expected a number > 0)"},
      {[&] { limits.integer("count", 1, 16); },
       "vehicle.yaml:6: limits.count: missing required key (expected an integer in [1, 16])"},
      {[&] { limits.boolean("armed"); },
       "vehicle.yaml:6: limits.armed: missing required key (expected true or false)"},
      {[&] { limits.string("label"); },
       "vehicle.yaml:6: limits.label: missing required key (expected a string)"},
      {[&] {
         limits.numbers("gains", 3, {0, 10});
       },
       "vehicle.yaml:6: limits.gains: missing required key (expected a sequence of 3 numbers "
       "(each a number in [0, 10]))"},
      {[&] {
         limits.choice("mode", {"x", "h"});
       },
       "vehicle.yaml:6: limits.mode: missing required key (expected one of: x, h)"},
      {[&] {
         limits.angle_deg("yaw_deg", {-180, 180});
       },
       "vehicle.yaml:6: limits.yaw_deg: missing required key (expected a number in [-180, 180] "
       "of degrees)"},
  };
  for (const auto& c : cases) EXPECT_EQ(error_of(c.read), c.message);
}

TEST(Config, DuplicateKeyIsAnErrorNamingBothLines) {
  EXPECT_EQ(error_of([] { Value::parse("a: 1\nb: 2\na: 3\n", "dup.yaml"); }),
            "dup.yaml:3: a: duplicate key (first at line 1)");
  EXPECT_EQ(error_of([] { Value::parse("limits:\n  max: 1\n  min: 0\n  max: 2\n", "dup.yaml"); }),
            "dup.yaml:4: limits.max: duplicate key (first at line 2)");
  EXPECT_EQ(error_of([] {
              Value::parse("thrusters:\n  - name: a\n  - name: b\n    name: c\n", "dup.yaml");
            }),
            "dup.yaml:4: thrusters[1].name: duplicate key (first at line 3)");
  // The same key in two different maps is fine.
  EXPECT_EQ(error_of([] { Value::parse("a:\n  x: 1\nb:\n  x: 2\n", "ok.yaml"); }), "(no error)");
}

TEST(Config, WrongTypeSaysWhatWasExpected) {
  const Value v = Value::parse(kDoc, "vehicle.yaml");
  EXPECT_EQ(error_of([&] { v.number("name"); }),
            "vehicle.yaml:1: name: expected a number, got 'otter'");
  EXPECT_EQ(error_of([&] { v.at("limits").numbers("names", 2); }),
            "vehicle.yaml:7: limits.names[0]: expected a number, got 'a'");
  EXPECT_EQ(
      error_of([&] { v.at("thrusters")[0].numbers("position", 2); }),
      "vehicle.yaml:10: thrusters[0].position: expected a sequence of 2 numbers, got a sequence");
  EXPECT_EQ(error_of([&] { v.boolean("rate_hz"); }),
            "vehicle.yaml:2: rate_hz: expected true or false, got '50'");
  EXPECT_EQ(error_of([&] { v.at("limits").string("names"); }),
            "vehicle.yaml:7: limits.names: expected a string, got a sequence");
}

TEST(Config, OutOfRange) {
  const Value v = Value::parse(kDoc, "vehicle.yaml");
  EXPECT_EQ(error_of([&] {
              v.at("limits").number("max", {0, 1});
            }),
            "vehicle.yaml:6: limits.max: expected a number in [0, 1], got '1.5'");
  EXPECT_EQ(error_of([&] { v.integer("rate_hz", 1, 10); }),
            "vehicle.yaml:2: rate_hz: expected an integer in [1, 10], got '50'");
  EXPECT_EQ(error_of([&] {
              v.choice("name", {"wamv", "rov"});
            }),
            "vehicle.yaml:1: name: expected one of: wamv, rov, got 'otter'");
}

TEST(Config, NonFiniteNumbersAreRejected) {
  const Value v = Value::parse("gain: .nan\nlimit: .inf\n", "g.yaml");
  EXPECT_EQ(error_of([&] { v.number("gain"); }),
            "g.yaml:1: gain: expected a finite number, got '.nan'");
  EXPECT_EQ(error_of([&] { v.number("limit"); }),
            "g.yaml:2: limit: expected a finite number, got '.inf'");
}

TEST(Config, UnknownKeyAnywhereIsAnError) {
  const Value v =
      Value::parse(kDoc + std::string("  - name: extra\n    positon: [1, 2, 3]\n"), "v.yaml");
  v.string("name");
  v.integer("rate_hz");
  v.boolean("enabled");
  v.angle_deg("heading_deg");
  v.at("limits").number("max");
  v.at("limits").at("names").mark_used();
  for (const auto& t : v.at("thrusters").items()) {
    t.string("name");
    if (t.has("position")) t.numbers("position", 3);
  }
  EXPECT_EQ(error_of([&] { v.check_all_used(); }),
            "v.yaml:14: thrusters[2].positon: unknown key (not used by this program; misspelt?)");
}

TEST(Config, AllUsedPasses) {
  const Value v = Value::parse("a: 1\nb:\n  c: 2\n", "ok.yaml");
  v.number("a");
  v.at("b").number("c");
  EXPECT_NO_THROW(v.check_all_used());
}

TEST(Config, DegreesOnlyUnderDegKeys) {
  const Value v = Value::parse("heading: 90\n", "d.yaml");
  EXPECT_THROW(v.angle_deg("heading"), Error);
}

TEST(Config, SyntaxErrorsAndMissingFiles) {
  EXPECT_EQ(error_of([] { Value::parse("a: [1, 2\nb: 3\n", "bad.yaml"); }).rfind("bad.yaml:", 0),
            0u);
  EXPECT_NE(
      error_of([] { Value::parse("a: [1, 2\nb: 3\n", "bad.yaml"); }).find("YAML syntax error"),
      std::string::npos);
  EXPECT_EQ(error_of([] { Value::load_file("/nonexistent/tiller.yaml"); }),
            "/nonexistent/tiller.yaml: cannot open config file");
  EXPECT_EQ(error_of([] { Value::parse("- 1\n- 2\n", "list.yaml"); }),
            "list.yaml: expected a map of keys at the top level, got a sequence");
}

TEST(Config, LoadsFromFile) {
  const std::string path = ::testing::TempDir() + "/tiller_config_test.yaml";
  {
    std::ofstream out(path);
    out << "rate_hz: 20\n";
  }
  const Value v = Value::load_file(path);
  EXPECT_EQ(v.integer("rate_hz"), 20);
  EXPECT_EQ(error_of([&] { v.integer("rate_hz", 50, 100); }),
            path + ":1: rate_hz: expected an integer in [50, 100], got '20'");
}

TEST(Angles, WrapPi) {
  EXPECT_DOUBLE_EQ(wrap_pi(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_pi(kPi), kPi);   // (-pi, pi]: pi stays
  EXPECT_DOUBLE_EQ(wrap_pi(-kPi), kPi);  // -pi maps to pi
  EXPECT_NEAR(wrap_pi(3 * kPi / 2), -kPi / 2, 1e-12);
  EXPECT_NEAR(wrap_pi(-7 * kPi / 2), kPi / 2, 1e-12);
  EXPECT_NEAR(angle_diff(deg_to_rad(10), deg_to_rad(350)), deg_to_rad(20), 1e-12);
  EXPECT_TRUE(std::isnan(wrap_pi(std::nan(""))));
}

}  // namespace
}  // namespace tiller::config

namespace tiller::config {
namespace {

// Every YAML file the repository ships parses under the strict rules (no duplicate keys).
TEST(Config, EveryShippedYamlParses) {
  int n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(TILLER_SOURCE_DIR "/config")) {
    if (e.path().extension() != ".yaml") continue;
    ++n;
    EXPECT_EQ(error_of([&] { Value::load_file(e.path().string()); }), "(no error)");
  }
  EXPECT_GT(n, 10);
}

}  // namespace
}  // namespace tiller::config
