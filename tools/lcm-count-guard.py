#!/usr/bin/env python3
"""Generates count_guard.hpp: a pre-decode check for every struct in lcmtypes/*.lcm.

lcm-gen 1.3.1's C++ decoders resize each variable-length array to the count read from the
packet before checking that the packet holds that many elements, so a short packet with a huge
count makes the receiver allocate gigabytes. The generated tiller::counts_fit<Msg>(data, size)
walks the encoded bytes exactly as LCM lays them out (big-endian; the 8-byte fingerprint first,
nested structs without one; string = int32 length including the NUL, then the bytes; boolean,
byte and int8_t one byte) and returns false when a count is negative, when the bytes left
cannot hold count x the element's minimum encoded size, or when the packet ends early. It
allocates nothing.

Usage: lcm-count-guard.py OUTPUT.hpp FILE.lcm...
Standard library only.
"""
import re
import sys

PRIMITIVE_SIZE = {
    "int8_t": 1, "byte": 1, "boolean": 1, "int16_t": 2, "int32_t": 4, "float": 4,
    "int64_t": 8, "double": 8,
}
INTEGER = {"int8_t": 1, "byte": 1, "int16_t": 2, "int32_t": 4, "int64_t": 8}
STRING_MIN = 5  # int32 length + at least the NUL
PACKAGE = "tiller"


class LcmError(Exception):
    pass


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def parse(path):
    """Returns [(struct name, [(type, name, [dims])])] for one .lcm file."""
    text = strip_comments(open(path, encoding="utf-8").read())
    pkg = re.search(r"\bpackage\s+([\w.]+)\s*;", text)
    if not pkg or pkg.group(1) != PACKAGE:
        raise LcmError(f"{path}: expected 'package {PACKAGE};'")
    structs = []
    for m in re.finditer(r"\bstruct\s+(\w+)\s*\{(.*?)\}", text, flags=re.S):
        name, body = m.group(1), m.group(2)
        fields = []
        for stmt in body.split(";"):
            stmt = " ".join(stmt.split())
            if not stmt or stmt.startswith("const "):
                continue
            f = re.fullmatch(r"([\w.]+)\s+(.+)", stmt)
            if not f:
                raise LcmError(f"{path}: struct {name}: cannot parse field '{stmt}'")
            ftype = f.group(1)
            if ftype.startswith(PACKAGE + "."):
                ftype = ftype[len(PACKAGE) + 1:]
            elif "." in ftype:
                raise LcmError(f"{path}: struct {name}: type {ftype} is not in package {PACKAGE}")
            for decl in f.group(2).split(","):
                d = re.fullmatch(r"\s*(\w+)\s*((?:\[\s*\w+\s*\]\s*)*)", decl)
                if not d:
                    raise LcmError(f"{path}: struct {name}: cannot parse declaration '{decl}'")
                dims = re.findall(r"\[\s*(\w+)\s*\]", d.group(2))
                fields.append((ftype, d.group(1), dims))
        structs.append((name, fields))
    if not structs:
        raise LcmError(f"{path}: no struct found")
    return structs


def min_size(tname, types, stack=()):
    if tname in PRIMITIVE_SIZE:
        return PRIMITIVE_SIZE[tname]
    if tname == "string":
        return STRING_MIN
    if tname not in types:
        raise LcmError(f"unknown type {tname}")
    if tname in stack:
        raise LcmError(f"recursive type {tname}")
    total = 0
    for ftype, _, dims in types[tname]:
        n = 1
        for d in dims:
            n = n * int(d) if d.isdigit() else 0
        total += n * min_size(ftype, types, stack + (tname,))
    return total


def emit_walk(name, fields, types):
    out = [f"inline bool walk_{name}(Reader& r) {{"]
    seen_int = {}
    counts = {d for _, _, dims in fields for d in dims if not d.isdigit()}
    for ftype, fname, dims in fields:
        for d in dims:
            if d.isdigit():
                continue
            if d not in seen_int:
                raise LcmError(f"struct {name}: array {fname}[{d}]: {d} is not an earlier integer field")
        elem = min_size(ftype, types)
        if elem <= 0:
            raise LcmError(f"struct {name}: field {fname}: type {ftype} has no minimum size to guard with")
        fixed = ftype in PRIMITIVE_SIZE
        if not dims:
            if fname in counts:
                if ftype not in INTEGER:
                    raise LcmError(f"struct {name}: count {fname} is not an integer")
                out.append(f"  std::int64_t {fname} = 0;")
                out.append(f"  if (!r.integer({PRIMITIVE_SIZE[ftype]}, {fname})) return false;")
            elif fixed:
                out.append(f"  if (!r.skip({elem})) return false;  // {fname}")
            elif ftype == "string":
                out.append(f"  if (!r.string()) return false;  // {fname}")
            else:
                out.append(f"  if (!walk_{ftype}(r)) return false;  // {fname}")
            if ftype in INTEGER:
                seen_int[fname] = True
            continue
        if fixed and all(d.isdigit() for d in dims):
            n = 1
            for d in dims:
                n *= int(d)
            out.append(f"  if (!r.skip({n * elem})) return false;  // {fname}" + "".join(f"[{d}]" for d in dims))
            continue
        out.append(f"  {{  // {fname}" + "".join(f"[{d}]" for d in dims))
        out.append("    std::int64_t c = 1;")
        for d in dims:
            out.append(f"    if (!r.times(c, {d})) return false;")
        out.append(f"    if (!r.room(c, {elem})) return false;")
        if fixed:
            out.append(f"    if (!r.skip(c * {elem})) return false;")
        else:
            call = "r.string()" if ftype == "string" else f"walk_{ftype}(r)"
            out.append(f"    for (std::int64_t i = 0; i < c; ++i)")
            out.append(f"      if (!{call}) return false;")
        out.append("  }")
    out.append("  return true;")
    out.append("}")
    return out


HEADER = """\
// Generated by tools/lcm-count-guard.py from lcmtypes/*.lcm. Do not edit.
// counts_fit<Msg>(data, size): false when the packet's array counts cannot fit in its bytes
// (negative count, count x minimum element size larger than what is left, packet ends early).
// Call it before Msg::decode: lcm-gen 1.3.1's decoders resize arrays to the packet's counts
// before they check that the bytes are there. Walks the bytes only; allocates nothing.
#pragma once

#include <cstdint>

namespace tiller {
%(forward)s

// Specialised below for every tiller type; a message type without a guard does not compile.
template <class Msg>
struct count_guard;

namespace count_guard_detail {

// Big-endian cursor over an encoded LCM message.
struct Reader {
  const unsigned char* p;
  std::int64_t left;

  bool skip(std::int64_t n) {
    if (n < 0 || n > left) return false;
    p += n;
    left -= n;
    return true;
  }
  // A signed integer of `bytes` bytes (1, 2, 4 or 8).
  bool integer(int bytes, std::int64_t& out) {
    if (bytes > left) return false;
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
    if (bytes < 8) {
      const std::uint64_t sign = std::uint64_t{1} << (8 * bytes - 1);
      v = (v ^ sign) - sign;  // sign-extend
    }
    out = static_cast<std::int64_t>(v);
    return skip(bytes);
  }
  // c *= dim, refusing a negative dimension and any product larger than the bytes left
  // (every element takes at least one byte).
  bool times(std::int64_t& c, std::int64_t dim) const {
    if (dim < 0) return false;
    if (dim != 0 && c > left / dim) return false;
    c *= dim;
    return true;
  }
  // The bytes left can hold `count` elements of at least `min_elem` bytes each.
  bool room(std::int64_t count, std::int64_t min_elem) const {
    return count >= 0 && count <= left / min_elem;
  }
  // int32 length including the trailing NUL, then that many bytes.
  bool string() {
    std::int64_t len = 0;
    if (!integer(4, len)) return false;
    return len >= 1 && skip(len);
  }
};

%(walks)s

}  // namespace count_guard_detail

%(specialisations)s

// The top-level message: the 8-byte fingerprint, then the fields.
template <class Msg>
bool counts_fit(const void* data, int size) {
  if (data == nullptr || size < 8) return false;
  count_guard_detail::Reader r{static_cast<const unsigned char*>(data), size};
  if (!r.skip(8)) return false;
  return count_guard<Msg>::walk(r);
}

// Every type the guard knows, in lcmtypes/ order (for tests).
inline constexpr const char* count_guard_types[] = {
%(names)s
};

}  // namespace tiller
"""


def main(argv):
    if len(argv) < 3:
        sys.stderr.write("usage: lcm-count-guard.py OUTPUT.hpp FILE.lcm...\n")
        return 2
    types = {}
    order = []
    try:
        for path in sorted(argv[2:]):
            for name, fields in parse(path):
                if name in types:
                    raise LcmError(f"{path}: struct {name} defined twice")
                types[name] = fields
                order.append(name)
        for name in order:
            for ftype, fname, _ in types[name]:
                if ftype not in PRIMITIVE_SIZE and ftype != "string" and ftype not in types:
                    raise LcmError(f"struct {name}: field {fname}: unknown type {ftype}")
        # Walk functions in dependency order (nested types first).
        done, walks = set(), []

        def visit(n, stack=()):
            if n in done:
                return
            if n in stack:
                raise LcmError(f"recursive type {n}")
            for ftype, _, _ in types[n]:
                if ftype in types:
                    visit(ftype, stack + (n,))
            walks.extend(emit_walk(n, types[n], types) + [""])
            done.add(n)

        for n in order:
            visit(n)
    except LcmError as e:
        sys.stderr.write(f"lcm-count-guard: {e}\n")
        return 1
    text = HEADER % {
        "forward": "\n".join(f"class {n};" for n in order),
        "walks": "\n".join(walks).rstrip(),
        "specialisations": "\n".join(
            f"template <>\nstruct count_guard<{n}> {{\n"
            f"  static bool walk(count_guard_detail::Reader& r) {{ return count_guard_detail::walk_{n}(r); }}\n"
            f"}};" for n in order),
        "names": "\n".join(f'    "{n}",' for n in order),
    }
    try:
        with open(argv[1], encoding="utf-8") as f:
            if f.read() == text:
                return 0
    except OSError:
        pass
    with open(argv[1], "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
