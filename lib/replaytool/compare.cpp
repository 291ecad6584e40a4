#include "replaytool/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "logtools/lcm_schema.hpp"
#include "runtime/channels.hpp"
#include "runtime/replay.hpp"

namespace tiller::replaytool {

namespace {
std::string fmt(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
}  // namespace

ChannelReport compare_channel(const std::string& channel, const std::vector<Event>& recorded,
                              const std::vector<Event>& replayed, const Tolerance& tol) {
  ChannelReport r;
  r.channel = channel;
  r.recorded = recorded.size();
  r.replayed = replayed.size();
  const auto& db = logtools::tiller_types();
  logtools::Decoded a, b;
  // Exact mode (no time tolerance): the i-th recorded message against the i-th replayed one.
  // With a time tolerance (live logs): each recorded message against the replayed one nearest
  // in time, which must lie within the tolerance; fields named *utime get the time tolerance.
  r.by_time = tol.time_us > 0;
  const std::size_t n = r.by_time ? recorded.size() : std::min(recorded.size(), replayed.size());
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Event& o = recorded[i];
    std::optional<Difference> diff;
    auto note = [&](const std::string& field, const std::string& ov, const std::string& nv) {
      if (!diff) diff = Difference{o.time, i, field, ov, nv};
    };
    if (r.by_time) {
      while (j + 1 < replayed.size() &&
             std::llabs(replayed[j + 1].time - o.time) <= std::llabs(replayed[j].time - o.time))
        ++j;
      if (replayed.empty() || std::llabs(replayed[j].time - o.time) > tol.time_us) {
        note("time", std::to_string(o.time),
             "no message within " + std::to_string(tol.time_us) + " us");
        ++r.differing;
        if (!r.first) r.first = diff;
        continue;
      }
    }
    const Event& w = r.by_time ? replayed[j] : replayed[i];
    if (std::llabs(o.time - w.time) > tol.time_us)
      note("time", std::to_string(o.time), std::to_string(w.time));
    if (o.data != w.data) {
      const bool da = db.decode(o.data.data(), o.data.size(), a);
      const bool dw = db.decode(w.data.data(), w.data.size(), b);
      if (!da || !dw) {
        note("bytes", da ? "decoded" : "undecodable", dw ? "decoded" : "undecodable");
      } else if (a.type != b.type) {
        note("type", a.type->name, b.type->name);
      } else {
        std::map<std::string, const logtools::FieldValue*> bf;
        for (const auto& f : b.fields) bf[f.path] = &f;
        std::set<std::string> seen;
        for (const auto& fa : a.fields) {
          seen.insert(fa.path);
          auto it = bf.find(fa.path);
          if (it == bf.end()) {
            note(fa.path, fa.to_string(), "(absent)");
            continue;
          }
          const auto& fb = *it->second;
          if (fa.is_text || fb.is_text) {
            if (fa.is_text != fb.is_text || fa.text != fb.text)
              note(fa.path, fa.to_string(), fb.to_string());
            continue;
          }
          const bool both_nan = std::isnan(fa.number) && std::isnan(fb.number);
          const double d = both_nan ? 0.0 : std::fabs(fa.number - fb.number);
          const bool is_time =
              fa.path.size() >= 5 && fa.path.compare(fa.path.size() - 5, 5, "utime") == 0;
          const double allowed = is_time && r.by_time ? static_cast<double>(tol.time_us) : tol.abs;
          if (!both_nan && !(d <= allowed)) note(fa.path, fmt(fa.number), fmt(fb.number));
          if (is_time && r.by_time) continue;  // not a value difference
          if (!std::isnan(d) && d > r.max_abs_diff) {
            r.max_abs_diff = d;
            r.max_abs_field = fa.path;
          } else if (std::isnan(d)) {
            r.max_abs_diff = NAN;
            r.max_abs_field = fa.path;
          }
        }
        for (const auto& fb : b.fields) {
          if (!seen.count(fb.path)) note(fb.path, "(absent)", fb.to_string());
        }
      }
    }
    if (diff) {
      ++r.differing;
      if (!r.first) r.first = diff;
    } else {
      ++r.matching;
    }
  }
  if (!r.by_time && recorded.size() != replayed.size() && !r.first) {
    const std::size_t i = n;
    const TimeUs t = i < recorded.size() ? recorded[i].time : replayed[i].time;
    r.first =
        Difference{t, i, "count", std::to_string(recorded.size()), std::to_string(replayed.size())};
  }
  return r;
}

bool ProcessReport::ok() const {
  return std::all_of(channels.begin(), channels.end(),
                     [](const ChannelReport& c) { return c.ok(); });
}

ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol, bool heartbeats) {
  ProcessReport rep;
  rep.process = entry.name;
  rep.config = config_path;
  std::unique_ptr<Node> node = entry.make(config_path);
  for (const auto& e : log) rep.inputs += node->subscribes_to(e.channel) ? 1 : 0;
  ReplayExecutor rx(*node);
  if (!log.empty()) rx.run(log, log.front().time, log.back().time);
  std::set<std::string> chans(entry.outputs.begin(), entry.outputs.end());
  for (const auto& e : rx.outputs()) chans.insert(e.channel);
  if (heartbeats) {
    chans.insert(node->heartbeat_channel());
  } else {
    chans.erase(node->heartbeat_channel());
  }
  for (const auto& ch : chans) {
    std::vector<Event> old_events, new_events;
    for (const auto& e : log)
      if (e.channel == ch) old_events.push_back(e);
    for (const auto& e : rx.outputs())
      if (e.channel == ch) new_events.push_back(e);
    rep.channels.push_back(compare_channel(ch, old_events, new_events, tol));
  }
  return rep;
}

std::string format_report(const ProcessReport& r) {
  std::ostringstream os;
  os << r.process << " (config " << r.config << ", " << r.inputs << " recorded inputs)\n";
  std::size_t w = 8;
  for (const auto& c : r.channels) w = std::max(w, c.channel.size());
  std::size_t bad = 0;
  for (const auto& c : r.channels) {
    std::string name = c.channel;
    name.resize(w, ' ');
    os << "  " << name << "  ";
    if (c.recorded == 0 && c.replayed == 0) {
      os << "no messages either way\n";
      continue;
    }
    if (c.ok()) {
      os << "matching (" << c.matching << " messages";
      if (c.max_abs_diff > 0)
        os << ", max |diff| " << fmt(c.max_abs_diff) << " in " << c.max_abs_field;
      os << ")\n";
      continue;
    }
    ++bad;
    os << "DIFFERENT: " << c.differing << " of " << std::min(c.recorded, c.replayed)
       << " messages differ";
    if (c.recorded != c.replayed) os << ", recorded " << c.recorded << " replayed " << c.replayed;
    os << "\n";
    if (c.first) {
      char t[32];
      std::snprintf(t, sizeof t, "%.6f", to_seconds(c.first->time));
      os << "    first difference: message " << c.first->index << " at t=" << t << " s, "
         << c.first->field << ": old " << c.first->old_value << ", new " << c.first->new_value
         << "\n";
    }
    if (c.max_abs_diff > 0)
      os << "    max |diff| " << fmt(c.max_abs_diff) << " in " << c.max_abs_field << "\n";
  }
  os << "  summary: " << r.channels.size() - bad << " of " << r.channels.size() << " channels match"
     << (bad ? "" : " -- PASS") << (bad ? " -- FAIL" : "") << "\n";
  return os.str();
}

}  // namespace tiller::replaytool
