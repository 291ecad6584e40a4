#include "logtools/lcm_schema.hpp"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <functional>
#include <set>
#include <stdexcept>

namespace tiller::logtools {

namespace {

const std::set<std::string> kPrimitive{"int8_t", "int16_t", "int32_t", "int64_t", "byte",
                                       "float",  "double",  "string",  "boolean"};

struct Lexer {
  const std::string& s;
  std::string source;
  std::size_t i = 0;
  int line = 1;
  void skip() {
    for (;;) {
      while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) {
        if (s[i] == '\n') ++line;
        ++i;
      }
      if (s.compare(i, 2, "//") == 0) {
        while (i < s.size() && s[i] != '\n') ++i;
      } else if (s.compare(i, 2, "/*") == 0) {
        const auto e = s.find("*/", i + 2);
        for (std::size_t k = i; k < std::min(e, s.size()); ++k)
          if (s[k] == '\n') ++line;
        i = e == std::string::npos ? s.size() : e + 2;
      } else {
        return;
      }
    }
  }
  bool done() {
    skip();
    return i >= s.size();
  }
  std::string token() {
    skip();
    if (i >= s.size()) fail("unexpected end of file");
    const char c = s[i];
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-') {
      const std::size_t b = i;
      while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '_' ||
                              s[i] == '.' || s[i] == '-'))
        ++i;
      return s.substr(b, i - b);
    }
    ++i;
    return std::string(1, c);
  }
  void expect(const std::string& t) {
    const std::string got = token();
    if (got != t) fail("expected '" + t + "', got '" + got + "'");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(source + ":" + std::to_string(line) + ": " + what);
  }
};

}  // namespace

std::vector<StructDef> parse_lcm(const std::string& text, const std::string& source) {
  Lexer lx{text, source};
  std::string package;
  std::vector<StructDef> out;
  while (!lx.done()) {
    const std::string t = lx.token();
    if (t == "package") {
      package = lx.token();
      lx.expect(";");
      continue;
    }
    if (t != "struct") lx.fail("expected 'package' or 'struct', got '" + t + "'");
    StructDef def;
    def.package = package;
    def.name = lx.token();
    lx.expect("{");
    for (;;) {
      std::string type = lx.token();
      if (type == "}") break;
      if (type == "const") {  // const TYPE NAME = VALUE [, NAME = VALUE] ;
        while (lx.token() != ";") {
        }
        continue;
      }
      if (const auto dot = type.rfind('.'); dot != std::string::npos) type = type.substr(dot + 1);
      for (;;) {
        FieldDef f;
        f.type = type;
        f.name = lx.token();
        std::string sep = lx.token();
        while (sep == "[") {
          Dim d;
          const std::string size = lx.token();
          if (std::isdigit(static_cast<unsigned char>(size[0]))) {
            d.size = std::stoi(size);
          } else {
            d.is_const = false;
            d.field = size;
          }
          f.dims.push_back(d);
          lx.expect("]");
          sep = lx.token();
        }
        def.fields.push_back(f);
        if (sep == ";") break;
        if (sep != ",") lx.fail("expected ';' after field " + f.name + ", got '" + sep + "'");
      }
    }
    out.push_back(std::move(def));
  }
  return out;
}

std::int64_t lcm_fingerprint(const StructDef& def, const std::map<std::string, StructDef>& all) {
  // lcmgen.c: base hash over member names, primitive type names and dimensions, then in the
  // generated code: (base + sum of nested types' hashes) rotated left by one bit.
  auto update = [](std::int64_t v, char c) {
    return static_cast<std::int64_t>((static_cast<std::uint64_t>(v) << 8) ^
                                     static_cast<std::uint64_t>(v >> 55)) +
           c;
  };
  auto update_str = [&](std::int64_t v, const std::string& s) {
    v = update(v, static_cast<char>(s.size()));
    for (char c : s) v = update(v, c);
    return v;
  };
  std::function<std::uint64_t(const StructDef&, std::vector<std::string>)> compute =
      [&](const StructDef& d, std::vector<std::string> parents) -> std::uint64_t {
    for (const auto& p : parents)
      if (p == d.name) return 0;
    std::int64_t v = 0x12345678;
    for (const auto& f : d.fields) {
      v = update_str(v, f.name);
      if (kPrimitive.count(f.type)) v = update_str(v, f.type);
      v = update(v, static_cast<char>(f.dims.size()));
      for (const auto& dim : f.dims) {
        v = update(v, dim.is_const ? 0 : 1);
        v = update_str(v, dim.is_const ? std::to_string(dim.size) : dim.field);
      }
    }
    std::uint64_t h = static_cast<std::uint64_t>(v);
    parents.push_back(d.name);
    for (const auto& f : d.fields) {
      if (kPrimitive.count(f.type)) continue;
      auto it = all.find(f.type);
      if (it == all.end()) throw std::runtime_error("unknown type " + f.type + " in " + d.name);
      h += compute(it->second, parents);
    }
    return (h << 1) + ((h >> 63) & 1);
  };
  return static_cast<std::int64_t>(compute(def, {}));
}

std::string FieldValue::to_string() const {
  if (is_text) return text;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", number);
  return buf;
}

const FieldValue* Decoded::find(const std::string& path) const {
  for (const auto& f : fields)
    if (f.path == path) return &f;
  return nullptr;
}

double Decoded::number(const std::string& path, double fallback) const {
  const FieldValue* f = find(path);
  return f && !f->is_text ? f->number : fallback;
}

void TypeDb::add(StructDef def) {
  by_hash_[def.hash] = def.name;
  by_name_[def.name] = std::move(def);
}

const StructDef* TypeDb::by_name(const std::string& name) const {
  auto it = by_name_.find(name);
  return it == by_name_.end() ? nullptr : &it->second;
}

const StructDef* TypeDb::by_hash(std::int64_t hash) const {
  auto it = by_hash_.find(hash);
  return it == by_hash_.end() ? nullptr : by_name(it->second);
}

std::vector<std::string> TypeDb::names() const {
  std::vector<std::string> v;
  for (const auto& [n, d] : by_name_) v.push_back(n);
  return v;
}

namespace {

struct Reader {
  const std::uint8_t* p;
  std::size_t n;
  std::size_t i = 0;
  bool ok = true;
  bool need(std::size_t k) {
    if (i + k > n) ok = false;
    return ok;
  }
  std::uint64_t be(std::size_t k) {
    if (!need(k)) return 0;
    std::uint64_t v = 0;
    for (std::size_t j = 0; j < k; ++j) v = (v << 8) | p[i + j];
    i += k;
    return v;
  }
};

bool read_primitive(Reader& r, const std::string& t, FieldValue& fv) {
  if (t == "int8_t")
    fv.number = static_cast<std::int8_t>(r.be(1));
  else if (t == "byte")
    fv.number = static_cast<std::uint8_t>(r.be(1));
  else if (t == "boolean")
    fv.number = r.be(1) != 0 ? 1.0 : 0.0;
  else if (t == "int16_t")
    fv.number = static_cast<std::int16_t>(r.be(2));
  else if (t == "int32_t")
    fv.number = static_cast<std::int32_t>(r.be(4));
  else if (t == "int64_t")
    fv.number = static_cast<double>(static_cast<std::int64_t>(r.be(8)));
  else if (t == "float") {
    const auto bits = static_cast<std::uint32_t>(r.be(4));
    float f;
    std::memcpy(&f, &bits, 4);
    fv.number = f;
  } else if (t == "double") {
    const auto bits = r.be(8);
    double d;
    std::memcpy(&d, &bits, 8);
    fv.number = d;
  } else if (t == "string") {
    const auto len = static_cast<std::int32_t>(r.be(4));
    if (len < 1 || !r.need(static_cast<std::size_t>(len))) return r.ok = false;
    fv.is_text = true;
    fv.text.assign(reinterpret_cast<const char*>(r.p + r.i), static_cast<std::size_t>(len - 1));
    r.i += static_cast<std::size_t>(len);
  } else {
    return false;
  }
  return r.ok;
}

bool decode_struct(const TypeDb& db, const StructDef& d, Reader& r, const std::string& prefix,
                   std::vector<FieldValue>& out);

bool decode_field(const TypeDb& db, const FieldDef& f, std::size_t dim, Reader& r,
                  const std::string& path, const std::map<std::string, std::int64_t>& ints,
                  std::vector<FieldValue>& out) {
  if (dim < f.dims.size()) {
    const Dim& d = f.dims[dim];
    std::int64_t count = d.size;
    if (!d.is_const) {
      auto it = ints.find(d.field);
      if (it == ints.end() || it->second < 0) return false;
      count = it->second;
    }
    if (count > 1'000'000) return false;
    for (std::int64_t k = 0; k < count; ++k) {
      if (!decode_field(db, f, dim + 1, r, path + "[" + std::to_string(k) + "]", ints, out))
        return false;
    }
    return true;
  }
  if (kPrimitive.count(f.type)) {
    FieldValue fv;
    fv.path = path;
    if (!read_primitive(r, f.type, fv)) return false;
    out.push_back(std::move(fv));
    return true;
  }
  const StructDef* sub = db.by_name(f.type);
  return sub && decode_struct(db, *sub, r, path + ".", out);
}

bool decode_struct(const TypeDb& db, const StructDef& d, Reader& r, const std::string& prefix,
                   std::vector<FieldValue>& out) {
  std::map<std::string, std::int64_t> ints;  // scalar integer fields, for variable dimensions
  for (const auto& f : d.fields) {
    const std::size_t before = out.size();
    if (!decode_field(db, f, 0, r, prefix + f.name, ints, out)) return false;
    if (f.dims.empty() && out.size() == before + 1 && !out.back().is_text) {
      ints[f.name] = static_cast<std::int64_t>(out.back().number);
    }
  }
  return true;
}

}  // namespace

bool TypeDb::decode(const std::uint8_t* data, std::size_t n, Decoded& out) const {
  out.type = nullptr;
  out.fields.clear();
  Reader r{data, n};
  const auto hash = static_cast<std::int64_t>(r.be(8));
  if (!r.ok) return false;
  out.type = by_hash(hash);
  if (!out.type) return false;
  return decode_struct(*this, *out.type, r, "", out.fields) && r.i == n;
}

}  // namespace tiller::logtools
