#include "logtools/log_commands.hpp"

#include <fstream>
#include <set>
#include <stdexcept>

#include "logtools/csv.hpp"
#include "logtools/lcm_schema.hpp"
#include "runtime/log.hpp"

namespace tiller::logtools {

int print_fields(const std::vector<Event>& events, const std::string& channel, std::ostream& out,
                 std::ostream& err) {
  if (events.empty()) return 1;
  Decoded d;
  if (!tiller_types().decode(events[0].data.data(), events[0].data.size(), d)) {
    err << "tiller-log: " << channel << " does not carry a Tiller type\n";
    return 1;
  }
  out << channel << ": " << d.type->name << "\n";
  for (const auto& f : d.fields) out << "  " << f.path << " = " << f.to_string() << "\n";
  return 0;
}

int export_csv(const std::vector<Event>& events, const std::string& channel,
               const std::vector<std::string>& fields, TimeUs t0, const std::string& output,
               std::ostream& out, std::ostream& err) {
  // Every --fields name must choose something; else list what there is.
  if (!fields.empty()) {
    std::vector<std::string> paths;
    std::set<std::string> seen;
    Decoded d;
    std::string type;
    for (const auto& e : events) {
      if (!tiller_types().decode(e.data.data(), e.data.size(), d)) continue;
      type = d.type->name;
      for (const auto& f : d.fields)
        if (seen.insert(f.path).second) paths.push_back(f.path);
    }
    for (const auto& w : fields) {
      bool any = false;
      for (const auto& path : paths) any = any || field_selected(path, {w});
      if (any) continue;
      std::string list;
      for (const auto& path : paths) list += (list.empty() ? "" : ", ") + path;
      err << "tiller-log: --fields: no field \"" << w << "\" in " << channel
          << (type.empty() ? "" : " (" + type + ")") << "; its fields: " << list << "\n";
      return 2;
    }
  }
  std::size_t skipped = 0;
  std::size_t rows = 0;
  if (output.empty()) {
    rows = write_csv(out, events, channel, fields, t0, &skipped);
  } else {
    std::ofstream f(output);
    if (!f) throw std::runtime_error("cannot write " + output);
    rows = write_csv(f, events, channel, fields, t0, &skipped);
    err << "tiller-log: " << rows << " rows to " << output << "\n";
  }
  if (skipped) err << "tiller-log: " << skipped << " messages did not decode and were skipped\n";
  return rows > 0 ? 0 : 1;
}

namespace {
// True when the encoded message is of a Tiller type whose first field is `int64_t utime`.
bool leads_with_utime(const std::vector<std::uint8_t>& d) {
  if (d.size() < 16) return false;
  std::uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | d[static_cast<std::size_t>(i)];
  const StructDef* t = tiller_types().by_hash(static_cast<std::int64_t>(hash));
  return t != nullptr && !t->fields.empty() && t->fields[0].name == "utime" &&
         t->fields[0].type == "int64_t" && t->fields[0].dims.empty();
}
}  // namespace

std::size_t shift_times(std::vector<Event>& events, TimeUs shift) {
  std::size_t moved = 0;
  for (Event& e : events) {
    e.time += shift;
    if (!leads_with_utime(e.data)) continue;
    std::uint64_t u = 0;  // big-endian, bytes 8..15 (LCM's encoding)
    for (int i = 8; i < 16; ++i) u = (u << 8) | e.data[static_cast<std::size_t>(i)];
    u = static_cast<std::uint64_t>(static_cast<std::int64_t>(u) + shift);
    for (int i = 15; i >= 8; --i) {
      e.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u & 0xFF);
      u >>= 8;
    }
    ++moved;
  }
  return moved;
}

int restamp_log(std::vector<Event> events, TimeUs start, const std::string& output,
                std::ostream& out, std::ostream& err) {
  if (events.empty()) {
    err << "tiller-log: restamp: the log has no events\n";
    return 1;
  }
  const TimeUs shift = start - events.front().time;
  const std::size_t moved = shift_times(events, shift);
  LogWriter w(output);
  for (const Event& e : events) w.write(e);
  out << "tiller-log: restamp: " << events.size() << " events (" << moved << " utimes) moved by "
      << to_seconds(shift) << " s into " << output << "\n";
  return 0;
}

}  // namespace tiller::logtools
