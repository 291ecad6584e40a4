#include "logtools/csv.hpp"

#include <cstdio>
#include <map>

#include "logtools/lcm_schema.hpp"

namespace tiller::logtools {

bool field_selected(const std::string& path, const std::vector<std::string>& wanted) {
  if (wanted.empty()) return true;
  for (const auto& w : wanted) {
    if (path == w) return true;
    if (path.size() > w.size() && path.compare(0, w.size(), w) == 0 &&
        (path[w.size()] == '.' || path[w.size()] == '['))
      return true;
  }
  return false;
}

namespace {
std::string quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}
}  // namespace

std::size_t write_csv(std::ostream& os, const std::vector<Event>& events,
                      const std::string& channel, const std::vector<std::string>& fields, TimeUs t0,
                      std::size_t* skipped) {
  const TypeDb& db = tiller_types();
  std::vector<std::pair<TimeUs, Decoded>> rows;
  std::vector<std::string> columns;
  std::map<std::string, std::size_t> column_of;
  std::size_t bad = 0;
  for (const auto& e : events) {
    if (e.channel != channel) continue;
    Decoded d;
    if (!db.decode(e.data.data(), e.data.size(), d)) {
      ++bad;
      continue;
    }
    for (const auto& f : d.fields) {
      if (field_selected(f.path, fields) && !column_of.count(f.path)) {
        column_of[f.path] = columns.size();
        columns.push_back(f.path);
      }
    }
    rows.emplace_back(e.time, std::move(d));
  }
  if (skipped) *skipped = bad;
  os << "t_s";
  for (const auto& c : columns) os << "," << quote(c);
  os << "\n";
  std::vector<std::string> cells;
  for (const auto& [t, d] : rows) {
    cells.assign(columns.size(), "");
    for (const auto& f : d.fields) {
      auto it = column_of.find(f.path);
      if (it != column_of.end()) cells[it->second] = quote(f.to_string());
    }
    char ts[40];
    std::snprintf(ts, sizeof ts, "%.6f", to_seconds(t - t0));
    os << ts;
    for (const auto& c : cells) os << "," << c;
    os << "\n";
  }
  return rows.size();
}

}  // namespace tiller::logtools
