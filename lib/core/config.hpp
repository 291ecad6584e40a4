// Strict YAML configuration access (yaml-cpp underneath, nowhere else in the tree).
//
// A config::Value is one node of a loaded document together with its key path. Every key that
// is read is remembered; check_all_used() then reports any key nobody asked for. Every error
// (missing key, unknown key, duplicate key, wrong type, out of range, bad file) throws
// config::Error whose message names the file, the line, the key path and what was expected:
//   config/vehicles/otter.yaml:12: thrusters[1].position: expected a sequence of 3 numbers, got 'x'
//   config/mixer/otter.yaml:4: limits.min: missing required key (expected a number in [0, 1])
//   config/mixer/otter.yaml:9: limits.max: duplicate key (first at line 5)
//   config/mixer/otter.yaml:3: limtis: unknown key (not used by this program; misspelt?)
// Angles: a key ending in "_deg" is read with angle_deg() and returned in radians; degrees are
// accepted nowhere else.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace YAML {
class Node;
}

namespace tiller::config {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Inclusive numeric range; defaults to "any finite number".
struct Range {
  double min = -std::numeric_limits<double>::max();
  double max = std::numeric_limits<double>::max();
  static Range at_least(double lo) { return {lo, std::numeric_limits<double>::max()}; }
  static Range positive() {
    return {std::numeric_limits<double>::min(), std::numeric_limits<double>::max()};
  }
};

class Value {
 public:
  // Loads a file; throws Error naming the file if it cannot be read or parsed.
  static Value load_file(const std::string& path);
  // Parses text; `name` stands in for the file name in messages.
  static Value parse(const std::string& text, const std::string& name = "<string>");

  ~Value();
  Value(const Value&);
  Value& operator=(const Value&);

  // Kind of this node.
  bool is_map() const;
  bool is_sequence() const;
  bool is_scalar() const;
  bool is_null() const;

  // Map access. at() requires the key; find() returns nothing when it is absent.
  bool has(std::string_view key) const;
  Value at(std::string_view key) const;
  // Same, and a missing key's message says what was expected there ("a number in [0, 1]").
  Value at(std::string_view key, std::string_view expected) const;
  std::optional<Value> find(std::string_view key) const;
  std::vector<std::string> keys() const;  // map keys in document order

  // Sequence access.
  std::size_t size() const;
  Value operator[](std::size_t i) const;
  std::vector<Value> items() const;

  // This node as a value.
  double as_number(Range r = {}) const;
  std::int64_t as_integer(std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                          std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  bool as_bool() const;
  std::string as_string() const;
  std::vector<double> as_numbers(std::size_t n, Range r = {}) const;  // n = 0: any length >= 1

  // Shorthands for a required child key.
  double number(std::string_view key, Range r = {}) const {
    return at(key, describe_range(r)).as_number(r);
  }
  std::int64_t integer(std::string_view key,
                       std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                       std::int64_t max = std::numeric_limits<std::int64_t>::max()) const {
    return at(key, describe_integer(min, max)).as_integer(min, max);
  }
  bool boolean(std::string_view key) const { return at(key, "true or false").as_bool(); }
  std::string string(std::string_view key) const { return at(key, "a string").as_string(); }
  std::vector<double> numbers(std::string_view key, std::size_t n, Range r = {}) const {
    return at(key, describe_numbers(n, r)).as_numbers(n, r);
  }

  // What a number in `r` is called in messages: "a number", "a number in [0, 1]",
  // "a number >= 0", "a number > 0".
  static std::string describe_range(Range r);
  static std::string describe_integer(std::int64_t min, std::int64_t max);
  static std::string describe_numbers(std::size_t n, Range r);
  // Optional child keys with a default.
  double number_or(std::string_view key, double fallback, Range r = {}) const;
  std::int64_t integer_or(std::string_view key, std::int64_t fallback,
                          std::int64_t min = std::numeric_limits<std::int64_t>::min(),
                          std::int64_t max = std::numeric_limits<std::int64_t>::max()) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  std::string string_or(std::string_view key, const std::string& fallback) const;
  // A string that must be one of `allowed`.
  std::string choice(std::string_view key, std::initializer_list<std::string_view> allowed) const;
  std::string choice_or(std::string_view key, const std::string& fallback,
                        std::initializer_list<std::string_view> allowed) const;
  // A key that must end in "_deg": the number in degrees, returned in radians.
  double angle_deg(std::string_view key, Range r_deg = {}) const;
  double angle_deg_or(std::string_view key, double fallback_rad, Range r_deg = {}) const;

  // Throws Error for the first key under this node that was never read (an unknown key,
  // most often a typo). Call once after building the structs from a document.
  void check_all_used() const;
  // Marks this node and everything under it as read (for sections another loader owns).
  void mark_used() const;

  // Replaces the value at a dotted key path under this map ("yaw.k_error") with `yaml_text`
  // parsed as YAML ("40", "linear", "[1, 2]", "{kp: 3}"), in this loaded document, before a
  // loader reads it (tiller-run --set). Every key on the way must be a map; the last key may be
  // absent (it is added, and the loader's check_all_used refuses it if nobody reads it).
  // Throws Error naming the file, the key path and the problem.
  void set(std::string_view dotted_path, const std::string& yaml_text) const;

  // Throws Error with this node's file, line and key path, and `expected`.
  [[noreturn]] void fail(std::string_view expected) const;
  const std::string& path() const { return path_; }
  const std::string& file() const;
  int line() const;  // 1-based, 0 when unknown

 private:
  struct Doc;
  Value(std::shared_ptr<Doc> doc, const YAML::Node& node, std::string path);
  std::shared_ptr<Doc> doc_;
  std::unique_ptr<YAML::Node> node_;
  std::string path_;
};

}  // namespace tiller::config
