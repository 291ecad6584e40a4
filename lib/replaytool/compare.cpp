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
                              const std::vector<Event>& replayed, const Tolerance& tol,
                              std::size_t show) {
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
  r.live_match = r.by_time ? tol.live_match : 1.0;
  const std::size_t n = r.by_time ? recorded.size() : std::min(recorded.size(), replayed.size());
  std::size_t j = 0;
  std::vector<bool> used(r.by_time ? replayed.size() : 0, false);
  std::map<std::string, std::pair<double, double>> sq;  // field -> (sum d^2, sum old^2)
  auto record_diff = [&](const std::optional<Difference>& d) {
    ++r.differing;
    if (!r.first) r.first = d;
    if (r.shown.size() < show) r.shown.push_back(*d);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Event& o = recorded[i];
    std::optional<Difference> diff;
    auto note = [&](const std::string& field, const std::string& ov, const std::string& nv) {
      if (!diff) diff = Difference{o.time, i, field, ov, nv};
    };
    if (r.by_time) {
      // In order: the next replayed message within the time tolerance (a replayed message
      // skipped over is an extra one); of the next few candidates, one with identical bytes.
      while (j < replayed.size() && replayed[j].time < o.time - tol.time_us) ++j;
      if (j >= replayed.size() || replayed[j].time > o.time + tol.time_us) {
        note("time", std::to_string(o.time),
             "no message within " + std::to_string(tol.time_us) + " us");
        record_diff(diff);
        continue;
      }
      for (std::size_t k = j; k < std::min(j + 4, replayed.size()); ++k) {
        if (replayed[k].time > o.time + tol.time_us) break;
        if (replayed[k].data == o.data) {
          j = k;
          break;
        }
      }
      used[j] = true;
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
          const double allowed = is_time && r.by_time ? static_cast<double>(tol.time_us)
                                                      : tol.abs + tol.rel * std::fabs(fa.number);
          if (!both_nan && !(d <= allowed)) note(fa.path, fmt(fa.number), fmt(fb.number));
          if (is_time && r.by_time) continue;  // not a value difference
          if (r.by_time && std::isfinite(d)) {
            auto& acc = sq[fa.path];
            acc.first += d * d;
            acc.second += fa.number * fa.number;
          }
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
      record_diff(diff);
    } else {
      ++r.matching;
    }
    if (r.by_time) ++j;
  }
  for (const auto& [field, acc] : sq) {
    const double rel = acc.first == 0 ? 0.0 : std::sqrt(acc.first / std::max(acc.second, 1e-300));
    if (rel > r.worst_rel_rms) {
      r.worst_rel_rms = rel;
      r.worst_rel_field = field;
    }
  }
  for (std::size_t k = 0; k < used.size(); ++k) {
    if (used[k]) continue;
    ++r.unmatched_replayed;
    if (r.shown.size() < show)
      r.shown.push_back(Difference{replayed[k].time, k, "count", "(none recorded near it)",
                                   "an extra replayed message"});
    if (!r.first && r.differing == 0)
      r.first = Difference{replayed[k].time, k, "count", "(none recorded near it)",
                           "an extra replayed message"};
  }
  if (!r.by_time && recorded.size() != replayed.size() && !r.first) {
    const std::size_t i = n;
    const TimeUs t = i < recorded.size() ? recorded[i].time : replayed[i].time;
    r.first =
        Difference{t, i, "count", std::to_string(recorded.size()), std::to_string(replayed.size())};
    if (r.shown.size() < show) r.shown.push_back(*r.first);
  }
  return r;
}

bool ProcessReport::ok() const {
  if (informational) return true;
  return std::all_of(channels.begin(), channels.end(),
                     [](const ChannelReport& c) { return c.ok(); });
}

namespace {

// The bus of a replayed node: collects what it publishes, stamped with the current time.
class StampBus : public Bus {
 public:
  TimeUs now = 0;
  std::vector<Event> out;
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    out.push_back(Event{std::string(channel), now, std::vector<std::uint8_t>(data, data + size)});
  }
};

// Live replay (see ReplayOptions::live). Returns false when the process left no output in the
// log (it did not run): nothing is replayed then.
bool run_live(Node& node, const std::vector<std::string>& outputs, const std::vector<Event>& log,
              StampBus& bus, ProcessReport& rep) {
  const auto pubs = node.published_channels();
  std::set<std::string> pub(pubs.begin(), pubs.end());
  for (const auto& o : outputs)  // a listed output this node does not advertise is another's
    if (node.advertises(o)) pub.insert(o);
  const TimeUs period = node.tick_period();
  const auto& db = logtools::tiller_types();
  logtools::Decoded d;
  TimeUs first = INT64_MAX, last = INT64_MIN;
  std::map<TimeUs, TimeUs> ran_at;  // grid time of a tick -> when its first output was logged
  for (const auto& e : log) {
    if (!pub.count(e.channel)) continue;
    first = std::min(first, e.time);
    last = std::max(last, e.time);
    if (!db.decode(e.data.data(), e.data.size(), d)) continue;
    const auto* u = d.find("utime");
    if (!u || u->is_text) continue;
    const auto t = static_cast<TimeUs>(u->number);
    if (node.next_tick_at_or_after(t) != t || e.time < t || e.time - t >= period) continue;
    ran_at.emplace(t, e.time);
  }
  if (first == INT64_MAX) return false;
  std::vector<TimeUs> lags;
  for (const auto& [t, at] : ran_at) lags.push_back(at - t);
  TimeUs lag = 0;
  if (!lags.empty()) {
    std::nth_element(lags.begin(), lags.begin() + lags.size() / 2, lags.end());
    lag = lags[lags.size() / 2];
  }
  rep.live_from = first;
  rep.live_to = last;
  // The process started at most one period before its first output.
  const TimeUs from = first - period;
  TimeUs tick = node.next_tick_at_or_after(from);
  auto run_time = [&](TimeUs t) {
    const auto it = ran_at.find(t);
    return it != ran_at.end() ? it->second : t + lag;
  };
  // An input logged before a tick's first output reached the log is taken as delivered before
  // that tick (the log's receive times stand in for the process's).
  auto tick_until = [&](TimeUs t) {
    while (tick <= last && run_time(tick) <= t) {
      bus.now = run_time(tick);
      rep.aligned_ticks += ran_at.count(tick);
      ++rep.ticks;
      node.tick(tick);
      tick += period;
    }
  };
  for (const auto& e : log) {
    if (e.time < from) continue;
    if (e.time > last) break;
    if (!node.subscribes_to(e.channel)) continue;
    tick_until(e.time);
    bus.now = e.time;
    ++rep.inputs;
    node.deliver(e.channel, e.data.data(), static_cast<int>(e.data.size()), e.time);
  }
  tick_until(last);
  bus.now = last;
  node.shutdown(last);  // tiller-launch stopped it with SIGTERM (its last words are recorded)
  return true;
}

}  // namespace

ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol, bool heartbeats) {
  ReplayOptions o;
  o.heartbeats = heartbeats;
  return replay_process(entry, config_path, log, tol, o);
}

ProcessReport replay_process(const ProcessEntry& entry, const std::string& config_path,
                             const std::vector<Event>& log, const Tolerance& tol,
                             const ReplayOptions& opt) {
  ProcessReport rep;
  rep.process = entry.name;
  rep.config = config_path;
  rep.live = opt.live;
  rep.informational = opt.live && entry.integrating;
  if (!log.empty()) rep.origin = log.front().time;
  std::unique_ptr<Node> node =
      entry.make_with_args ? entry.make_with_args(config_path, opt.args) : entry.make(config_path);
  if (entry.prime) entry.prime(*node, log);
  std::vector<Event> outputs;
  TimeUs cmp_from = INT64_MIN, cmp_to = INT64_MAX;
  if (opt.live) {
    StampBus bus;
    node->attach(&bus);
    const bool ran = run_live(*node, entry.outputs, log, bus, rep);
    node->attach(nullptr);
    outputs = std::move(bus.out);
    if (ran) {
      cmp_from = rep.live_from;
      cmp_to = rep.live_to;
    }
  } else {
    for (const auto& e : log) rep.inputs += node->subscribes_to(e.channel) ? 1 : 0;
    ReplayExecutor rx(*node);
    if (!log.empty()) rx.run(log, log.front().time, log.back().time);
    outputs = rx.outputs();
  }
  // The entry's outputs that this node advertises (tiller-sim --odometry estimated publishes no
  // TILLER_ODOMETRY: in its log that channel is tiller-nav's), and whatever it published.
  std::set<std::string> chans;
  for (const auto& ch : entry.outputs)
    if (node->advertises(ch)) chans.insert(ch);
  for (const auto& e : outputs) chans.insert(e.channel);
  if (opt.heartbeats) {
    chans.insert(node->heartbeat_channel());
  } else {
    chans.erase(node->heartbeat_channel());
  }
  for (const auto& ch : chans) {
    std::vector<Event> old_events, new_events;
    for (const auto& e : log)
      if (e.channel == ch && e.time >= cmp_from && e.time <= cmp_to) old_events.push_back(e);
    for (const auto& e : outputs)
      if (e.channel == ch) new_events.push_back(e);
    rep.channels.push_back(compare_channel(ch, old_events, new_events, tol, opt.show));
  }
  return rep;
}

std::string format_report(const ProcessReport& r) {
  std::ostringstream os;
  os << r.process << " (config " << r.config << ", " << r.inputs << " recorded inputs)\n";
  auto rel = [&](TimeUs t) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6f", to_seconds(t - r.origin));
    return std::string(b);
  };
  if (r.live) {
    if (r.live_to > r.live_from)
      os << "  live log: replayed from t=" << rel(r.live_from) << " to t=" << rel(r.live_to)
         << " s (the process's first and last output), " << r.aligned_ticks << " of " << r.ticks
         << " ticks where the recording ran them\n";
    else
      os << "  live log: the process published nothing in the log (did it run?)\n";
  }
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
    if (c.ok() && c.by_time && (c.differing > 0 || c.unmatched_replayed > 0)) {
      os << "matching " << c.matching << " of " << c.recorded << " messages (at least "
         << c.live_match * 100 << "% needed";
      if (c.unmatched_replayed) os << ", " << c.unmatched_replayed << " extra replayed";
      os << ")\n";
      if (!c.shown.empty())
        os << "    first difference: message " << c.shown[0].index
           << " at t=" << rel(c.shown[0].time) << " s, " << c.shown[0].field << ": old "
           << c.shown[0].old_value << ", new " << c.shown[0].new_value << "\n";
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
    os << "DIFFERENT: " << c.differing << " of "
       << (c.by_time ? c.recorded : std::min(c.recorded, c.replayed)) << " messages differ";
    if (c.recorded != c.replayed) os << ", recorded " << c.recorded << " replayed " << c.replayed;
    if (c.unmatched_replayed) os << ", " << c.unmatched_replayed << " extra replayed";
    os << "\n";
    std::vector<Difference> list = c.shown;
    if (list.empty() && c.first) list.push_back(*c.first);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const auto& d = list[k];
      os << "    " << (k == 0 ? "first difference" : "then") << ": message " << d.index
         << " at t=" << rel(d.time) << " s, " << d.field << ": old " << d.old_value << ", new "
         << d.new_value << "\n";
    }
    if (c.max_abs_diff > 0)
      os << "    max |diff| " << fmt(c.max_abs_diff) << " in " << c.max_abs_field << "\n";
    if (c.by_time && c.worst_rel_rms > 0)
      os << "    worst relative rms difference " << c.worst_rel_rms << " in " << c.worst_rel_field
         << "\n";
  }
  os << "  summary: " << r.channels.size() - bad << " of " << r.channels.size()
     << " channels match";
  if (r.informational)
    os << " -- not in the verdict: its outputs integrate its inputs, so a live log cannot be\n"
          "     reproduced once one tick saw an input in another order (the golden lockstep logs\n"
          "     test it: test/ops/golden_test.sh)\n";
  else
    os << (bad ? " -- FAIL" : " -- PASS") << "\n";
  return os.str();
}

}  // namespace tiller::replaytool
