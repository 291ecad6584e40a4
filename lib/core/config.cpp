#include "core/config.hpp"
#include "core/config_files.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace tiller::config {

struct Value::Doc {
  std::string file;
  YAML::Node root;
  std::set<std::string> used;  // key paths that were read
};

namespace {

std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Scalar:
      return "'" + n.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a sequence";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "an undefined node";
  }
}

std::string join_path(const std::string& parent, std::string_view key) {
  if (parent.empty()) return std::string(key);
  return parent + "." + std::string(key);
}

// yaml-cpp keeps both entries of a key given twice in one map and reads the first: a silent
// trap (the second value, usually the one being edited, is ignored). Refuse it.
void check_duplicates(const std::string& file, const YAML::Node& n, const std::string& path) {
  if (n.IsMap()) {
    std::map<std::string, int> first_line;
    for (const auto& kv : n) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
      const int line = kv.first.Mark().is_null() ? 0 : kv.first.Mark().line + 1;
      const std::string p = join_path(path, key);
      auto [it, fresh] = first_line.emplace(key, line);
      if (!fresh) {
        throw Error(file + ":" + std::to_string(line) + ": " + p +
                    ": duplicate key (first at line " + std::to_string(it->second) + ")");
      }
      check_duplicates(file, kv.second, p);
    }
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      check_duplicates(file, n[i], path + "[" + std::to_string(i) + "]");
  }
}

std::string number_text(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

std::string Value::describe_range(Range r) {
  constexpr double kMax = std::numeric_limits<double>::max();
  const bool lo = r.min > -kMax, hi = r.max < kMax;
  if (!lo && !hi) return "a number";
  if (lo && hi) return "a number in [" + number_text(r.min) + ", " + number_text(r.max) + "]";
  if (hi) return "a number <= " + number_text(r.max);
  if (r.min == std::numeric_limits<double>::min()) return "a number > 0";
  return "a number >= " + number_text(r.min);
}

std::string Value::describe_integer(std::int64_t min, std::int64_t max) {
  const bool lo = min > std::numeric_limits<std::int64_t>::min();
  const bool hi = max < std::numeric_limits<std::int64_t>::max();
  if (!lo && !hi) return "an integer";
  if (lo && hi) return "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (hi) return "an integer <= " + std::to_string(max);
  return "an integer >= " + std::to_string(min);
}

std::string Value::describe_numbers(std::size_t n, Range r) {
  std::string d = describe_range(r);
  d = d.substr(2);  // "number in [0, 1]"
  return n ? "a sequence of " + std::to_string(n) + " numbers" +
                 (d == "number" ? "" : " (each a " + d + ")")
           : "a non-empty sequence of numbers" + (d == "number" ? "" : " (each a " + d + ")");
}

Value::Value(std::shared_ptr<Doc> doc, const YAML::Node& node, std::string path)
    : doc_(std::move(doc)), node_(std::make_unique<YAML::Node>(node)), path_(std::move(path)) {}

Value::~Value() = default;
Value::Value(const Value& o)
    : doc_(o.doc_), node_(std::make_unique<YAML::Node>(*o.node_)), path_(o.path_) {}
Value& Value::operator=(const Value& o) {
  if (this != &o) {
    doc_ = o.doc_;
    node_ = std::make_unique<YAML::Node>(*o.node_);
    path_ = o.path_;
  }
  return *this;
}

Value Value::load_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

Value Value::parse(const std::string& text, const std::string& name) {
  auto doc = std::make_shared<Doc>();
  doc->file = name;
  try {
    doc->root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw Error(name + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  if (!doc->root.IsMap()) {
    throw Error(name + ": expected a map of keys at the top level, got " + describe(doc->root));
  }
  check_duplicates(name, doc->root, "");
  YAML::Node root = doc->root;
  return Value(doc, root, "");
}

const std::string& Value::file() const {
  return doc_->file;
}

int Value::line() const {
  const auto m = node_->Mark();
  return m.is_null() ? 0 : m.line + 1;
}

void Value::fail(std::string_view expected) const {
  std::string msg = doc_->file;
  if (line() > 0) msg += ":" + std::to_string(line());
  msg += ": " + (path_.empty() ? std::string("(top level)") : path_) + ": expected " +
         std::string(expected) + ", got " + describe(*node_);
  throw Error(msg);
}

bool Value::is_map() const {
  return node_->IsMap();
}
bool Value::is_sequence() const {
  return node_->IsSequence();
}
bool Value::is_scalar() const {
  return node_->IsScalar();
}
bool Value::is_null() const {
  return node_->IsNull();
}

bool Value::has(std::string_view key) const {
  return node_->IsMap() && (*node_)[std::string(key)].IsDefined();
}

std::optional<Value> Value::find(std::string_view key) const {
  if (!node_->IsMap()) fail("a map of keys");
  const YAML::Node child = (*node_)[std::string(key)];
  if (!child.IsDefined()) return std::nullopt;
  std::string p = join_path(path_, key);
  doc_->used.insert(p);
  return Value(doc_, child, p);
}

void Value::set(std::string_view dotted_path, const std::string& yaml_text) const {
  const std::string where = doc_->file + ": " + join_path(path_, dotted_path);
  std::vector<std::string> parts;
  for (std::size_t b = 0; b <= dotted_path.size();) {
    const std::size_t e = std::min(dotted_path.find('.', b), dotted_path.size());
    parts.emplace_back(dotted_path.substr(b, e - b));
    if (parts.back().empty()) throw Error(where + ": expected a key path like a.b.c");
    b = e + 1;
  }
  YAML::Node value;
  try {
    value = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw Error(where + ": cannot set to '" + yaml_text + "': YAML syntax error: " + e.msg);
  }
  if (value.IsNull() && yaml_text.find_first_not_of(" \t") == std::string::npos) {
    throw Error(where + ": expected a value after '=', got nothing");
  }
  YAML::Node n = *node_;  // shares the document's node: changes go into the document
  std::string p = path_;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    p = join_path(p, parts[i]);
    if (!n.IsMap()) throw Error(where + ": cannot set: " + p + " is not a map of keys");
    const YAML::Node& cn = n;
    const YAML::Node child = cn[parts[i]];
    if (!child.IsDefined()) throw Error(where + ": cannot set: no key " + p + " in the file");
    n.reset(child);
  }
  if (!n.IsMap())
    throw Error(where + ": cannot set: " + (p.empty() ? "(top level)" : p) +
                " is not a map of keys");
  n[parts.back()] = value;
}

Value Value::at(std::string_view key) const {
  return at(key, "");
}

Value Value::at(std::string_view key, std::string_view expected) const {
  auto v = find(key);
  if (!v) {
    std::string msg = doc_->file;
    if (line() > 0) msg += ":" + std::to_string(line());
    msg += ": " + join_path(path_, key) + ": missing required key";
    if (!expected.empty()) msg += " (expected " + std::string(expected) + ")";
    throw Error(msg);
  }
  return *v;
}

std::vector<std::string> Value::keys() const {
  if (!node_->IsMap()) fail("a map of keys");
  std::vector<std::string> out;
  for (const auto& kv : *node_) out.push_back(kv.first.as<std::string>());
  return out;
}

std::size_t Value::size() const {
  if (!node_->IsSequence()) fail("a sequence");
  return node_->size();
}

Value Value::operator[](std::size_t i) const {
  if (!node_->IsSequence()) fail("a sequence");
  if (i >= node_->size()) fail("at least " + std::to_string(i + 1) + " items");
  std::string p = path_ + "[" + std::to_string(i) + "]";
  doc_->used.insert(p);
  return Value(doc_, (*node_)[i], p);
}

std::vector<Value> Value::items() const {
  std::vector<Value> out;
  const std::size_t n = size();
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back((*this)[i]);
  return out;
}

double Value::as_number(Range r) const {
  if (!node_->IsScalar()) fail("a number");
  double v = 0;
  try {
    v = node_->as<double>();
  } catch (const YAML::Exception&) {
    fail("a number");
  }
  if (!std::isfinite(v)) fail("a finite number");
  if (v < r.min || v > r.max) fail(describe_range(r));
  return v;
}

std::int64_t Value::as_integer(std::int64_t min, std::int64_t max) const {
  if (!node_->IsScalar()) fail("an integer");
  std::int64_t v = 0;
  try {
    v = node_->as<std::int64_t>();
  } catch (const YAML::Exception&) {
    fail("an integer");
  }
  if (v < min || v > max) fail(describe_integer(min, max));
  return v;
}

bool Value::as_bool() const {
  if (!node_->IsScalar()) fail("true or false");
  const std::string& s = node_->Scalar();
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  fail("true or false");
}

std::string Value::as_string() const {
  if (!node_->IsScalar()) fail("a string");
  return node_->Scalar();
}

std::vector<double> Value::as_numbers(std::size_t n, Range r) const {
  const std::string expect =
      n ? "a sequence of " + std::to_string(n) + " numbers" : "a non-empty sequence of numbers";
  if (!node_->IsSequence()) fail(expect);
  if ((n && node_->size() != n) || node_->size() == 0) fail(expect);
  std::vector<double> out;
  for (std::size_t i = 0; i < node_->size(); ++i) out.push_back((*this)[i].as_number(r));
  return out;
}

double Value::number_or(std::string_view key, double fallback, Range r) const {
  auto v = find(key);
  return v ? v->as_number(r) : fallback;
}
std::int64_t Value::integer_or(std::string_view key, std::int64_t fallback, std::int64_t min,
                               std::int64_t max) const {
  auto v = find(key);
  return v ? v->as_integer(min, max) : fallback;
}
bool Value::boolean_or(std::string_view key, bool fallback) const {
  auto v = find(key);
  return v ? v->as_bool() : fallback;
}
std::string Value::string_or(std::string_view key, const std::string& fallback) const {
  auto v = find(key);
  return v ? v->as_string() : fallback;
}

std::string Value::choice(std::string_view key,
                          std::initializer_list<std::string_view> allowed) const {
  std::string list;
  for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
  const Value v = at(key, "one of: " + list);
  const std::string s = v.as_string();
  for (auto a : allowed)
    if (s == a) return s;
  v.fail("one of: " + list);
}

std::string Value::choice_or(std::string_view key, const std::string& fallback,
                             std::initializer_list<std::string_view> allowed) const {
  return has(key) ? choice(key, allowed) : fallback;
}

double Value::angle_deg(std::string_view key, Range r_deg) const {
  if (key.size() < 4 || key.substr(key.size() - 4) != "_deg") {
    throw Error("internal: angle_deg() used with key '" + std::string(key) +
                "', which does not end in _deg");
  }
  return at(key, describe_range(r_deg) + " of degrees").as_number(r_deg) * M_PI / 180.0;
}

double Value::angle_deg_or(std::string_view key, double fallback_rad, Range r_deg) const {
  return has(key) ? angle_deg(key, r_deg) : fallback_rad;
}

void Value::check_all_used() const {
  // Depth-first over the tree: the first map key whose path was never read is an error.
  struct Walker {
    const Doc& doc;
    void walk(const YAML::Node& n, const std::string& path) const {
      if (n.IsMap()) {
        for (const auto& kv : n) {
          const std::string key = kv.first.as<std::string>();
          const std::string p = join_path(path, key);
          if (!doc.used.count(p)) {
            std::string msg = doc.file;
            const auto m = kv.first.Mark();
            if (!m.is_null()) msg += ":" + std::to_string(m.line + 1);
            msg += ": " + p + ": unknown key (not used by this program; misspelt?)";
            throw Error(msg);
          }
          walk(kv.second, p);
        }
      } else if (n.IsSequence()) {
        for (std::size_t i = 0; i < n.size(); ++i) {
          walk(n[i], path + "[" + std::to_string(i) + "]");
        }
      }
    }
  };
  Walker{*doc_}.walk(*node_, path_);
}

void Value::mark_used() const {
  struct Marker {
    Doc& doc;
    void walk(const YAML::Node& n, const std::string& path) const {
      if (n.IsMap()) {
        for (const auto& kv : n) {
          const std::string p = join_path(path, kv.first.as<std::string>());
          doc.used.insert(p);
          walk(kv.second, p);
        }
      } else if (n.IsSequence()) {
        for (std::size_t i = 0; i < n.size(); ++i) walk(n[i], path + "[" + std::to_string(i) + "]");
      }
    }
  };
  doc_->used.insert(path_);
  Marker{*doc_}.walk(*node_, path_);
}

std::string resolve_near(const std::string& rel, const std::string& config_file) {
  namespace fs = std::filesystem;
  if (fs::path(rel).is_absolute() || config_file.empty()) return rel;
  for (fs::path dir = fs::absolute(config_file).parent_path();; dir = dir.parent_path()) {
    if (fs::exists(dir / rel)) return (dir / rel).lexically_normal().string();
    if (dir == dir.root_path() || dir.empty()) break;
  }
  return rel;
}

}  // namespace tiller::config
