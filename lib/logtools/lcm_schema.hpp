// Tiller's message types read from their .lcm definitions at run time, so tools can decode any
// logged message field by field without a hand-written visitor per type: the log summary, the
// CSV export, the plots and the replay diff all go through this.
//
// A message is identified by its LCM fingerprint (the first 8 bytes of every encoded message);
// the fingerprints come from the generated C++ types, so decoding can never silently use a
// definition that differs from the one the programs were built with. Fields come out flat,
// in definition order, with paths like "position[1]" or "waypoints[2].heading"; numbers
// (all integer types, booleans as 0/1, floats) as double, strings as text. Big-endian, as LCM.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace tiller::logtools {

struct Dim {
  bool is_const = true;
  int size = 0;       // when is_const
  std::string field;  // name of an earlier integer field when variable
};

struct FieldDef {
  std::string type;  // primitive (int8_t.. double, string, boolean, byte) or a struct name
  std::string name;
  std::vector<Dim> dims;
};

struct StructDef {
  std::string package;
  std::string name;  // without package, e.g. "odometry_t"
  std::vector<FieldDef> fields;
  std::int64_t hash = 0;  // fingerprint as it appears in encoded messages
};

// Parses the structs of one .lcm file (constants and comments skipped). Throws
// std::runtime_error naming `source` and the line on a syntax it does not understand.
std::vector<StructDef> parse_lcm(const std::string& text, const std::string& source);

// The fingerprint lcm-gen computes for `def` (nested structs looked up in `all`).
std::int64_t lcm_fingerprint(const StructDef& def, const std::map<std::string, StructDef>& all);

struct FieldValue {
  std::string path;
  bool is_text = false;
  double number = 0.0;
  std::string text;
  std::string to_string() const;  // the number printed exactly (%.17g) or the text
};

struct Decoded {
  const StructDef* type = nullptr;
  std::vector<FieldValue> fields;
  const FieldValue* find(const std::string& path) const;
  double number(const std::string& path, double fallback = 0.0) const;
};

class TypeDb {
 public:
  // Adds a struct; its hash must be set (see tiller_types()).
  void add(StructDef def);
  const StructDef* by_name(const std::string& name) const;
  const StructDef* by_hash(std::int64_t hash) const;
  std::vector<std::string> names() const;
  // Decodes one encoded message (with its fingerprint). False: unknown type or malformed bytes
  // (`out.type` stays null for an unknown type).
  bool decode(const std::uint8_t* data, std::size_t n, Decoded& out) const;

 private:
  std::map<std::string, StructDef> by_name_;
  std::map<std::int64_t, std::string> by_hash_;
};

// Every type in lcmtypes/, with the fingerprints of the generated C++ types (embedded at build).
const TypeDb& tiller_types();

}  // namespace tiller::logtools
