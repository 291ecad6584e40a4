// JsonWriter: appends JSON text to a reused std::string (tiller-cockpit's WebSocket frames).
// Numbers are written in the shortest form that reads back to the same value (std::to_chars);
// a non-finite double (NaN, infinity), which JSON cannot carry, is written as null. Strings are
// escaped as RFC 8259 requires (quote, backslash, control characters as \uXXXX; bytes >= 0x80
// are copied, so UTF-8 passes through). Commas between members and elements are inserted by the
// writer; nesting is at most kMaxDepth deep. Nothing is allocated once the string's capacity is
// large enough.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace tiller::cockpit {

class JsonWriter {
 public:
  static constexpr int kMaxDepth = 32;
  explicit JsonWriter(std::string& out) : out_(out) {}

  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }
  // A member name inside an object; the value follows.
  void key(std::string_view k);
  void number(double v);
  void number(float v) { number(static_cast<double>(v)); }
  void number(std::int64_t v);
  void number(std::int32_t v) { number(static_cast<std::int64_t>(v)); }
  void number(std::int16_t v) { number(static_cast<std::int64_t>(v)); }
  void number(std::int8_t v) { number(static_cast<std::int64_t>(v)); }
  void number(std::uint8_t v) { number(static_cast<std::int64_t>(v)); }
  void boolean(bool v);
  void string(std::string_view s);
  void null();
  // Already-encoded JSON, written as one value.
  void raw(std::string_view json);

 private:
  void open(char c);
  void close(char c);
  void separate();  // a comma before the second and later values of the current container

  std::string& out_;
  bool first_[kMaxDepth + 1] = {true};
  int depth_ = 0;
  bool after_key_ = false;
};

}  // namespace tiller::cockpit
