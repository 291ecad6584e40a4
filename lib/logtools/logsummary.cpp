#include "logtools/logsummary.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include <tiller/heartbeat_t.hpp>

#include "logtools/lcm_schema.hpp"
#include "runtime/channels.hpp"

namespace tiller::logtools {

double ProcessHealth::missed_fraction() const {
  if (ticks_run < 0) return -1.0;
  const std::int64_t all = ticks_run + ticks_missed;
  return all > 0 ? static_cast<double>(ticks_missed) / static_cast<double>(all) : 0.0;
}

namespace {
const char* state_name(int state) {
  return state == heartbeat_t::STATE_OK         ? "ok"
         : state == heartbeat_t::STATE_DEGRADED ? "DEGRADED"
                                                : "FAULT";
}

// Counters that mean an input was dropped or something went wrong.
bool is_drop_counter(const std::string& name) {
  for (const char* p :
       {"rejected.", "malformed.", "exception.", "unadvertised.", "overrun.", "fault."})
    if (name.rfind(p, 0) == 0) return true;
  return false;
}

std::vector<std::string> attention(const LogSummary& s) {
  std::vector<std::string> out;
  char buf[256];
  for (const auto& p : s.processes) {
    const double f = p.missed_fraction();
    if (f > kMissedTicksLimit) {
      std::snprintf(buf, sizeof buf, "%s: missed %lld of %lld ticks (%.1f %%, above %.0f %%)",
                    p.process.c_str(), static_cast<long long>(p.ticks_missed),
                    static_cast<long long>(p.ticks_run + p.ticks_missed), 100.0 * f,
                    100.0 * kMissedTicksLimit);
      out.push_back(buf);
    } else if (f < 0 && p.ticks_missed > 0) {
      out.push_back(p.process + ": missed " + std::to_string(p.ticks_missed) +
                    " ticks (the log does not say how many ran)");
    }
    if (p.worst_state != heartbeat_t::STATE_OK) {
      std::snprintf(buf, sizeof buf, "%s: %s from %.1f s (\"%s\")%s", p.process.c_str(),
                    state_name(p.worst_state), to_seconds(p.worst_at - s.start),
                    p.worst_status.c_str(),
                    p.state == heartbeat_t::STATE_OK ? ", ok again by its last heartbeat" : "");
      out.push_back(buf);
    }
    std::string drops;
    for (const auto& [name, v] : p.counters)
      if (is_drop_counter(name))
        drops += (drops.empty() ? "" : ", ") + name + " = " + std::to_string(v);
    if (p.rejected > 0 || p.stale > 0 || !drops.empty())
      out.push_back(p.process + ": rejected " + std::to_string(p.rejected) + ", stale " +
                    std::to_string(p.stale) + (drops.empty() ? "" : " (" + drops + ")"));
    if (auto rt = p.counters.find("realtime.refused"); rt != p.counters.end() && rt->second > 0)
      out.push_back(p.process +
                    ": real time asked for and refused (realtime.refused = 1): it ran on the "
                    "normal scheduler; its first output lines say what is missing (docs/"
                    "operations.md, \"Real time\")");
  }
  for (const auto& c : s.channels)
    if (c.undecodable > 0)
      out.push_back(c.channel + ": " + std::to_string(c.undecodable) + " of " +
                    std::to_string(c.count) + " messages do not decode");
  return out;
}
}  // namespace

LogSummary summarize(const std::vector<Event>& events) {
  LogSummary s;
  s.events = static_cast<std::int64_t>(events.size());
  if (events.empty()) return s;
  s.start = events.front().time;
  s.end = events.front().time;
  std::map<std::string, std::vector<TimeUs>> times;
  std::map<std::string, ChannelStats> stats;
  std::map<std::string, ProcessHealth> health;
  const TypeDb& db = tiller_types();
  Decoded dec;
  const std::string hb_prefix = channels::kHeartbeatPrefix;
  for (const auto& e : events) {
    s.start = std::min(s.start, e.time);
    s.end = std::max(s.end, e.time);
    auto& st = stats[e.channel];
    if (st.count == 0) {
      st.channel = e.channel;
      st.first = e.time;
      st.type = "?";
      if (e.data.size() >= 8) {
        std::int64_t h = 0;
        for (int k = 0; k < 8; ++k)
          h = static_cast<std::int64_t>((static_cast<std::uint64_t>(h) << 8) |
                                        e.data[static_cast<std::size_t>(k)]);
        if (const StructDef* d = db.by_hash(h)) st.type = d->name;
      }
    }
    ++st.count;
    st.bytes += static_cast<std::int64_t>(e.data.size());
    st.last = e.time;
    times[e.channel].push_back(e.time);
    if (e.channel.rfind(hb_prefix, 0) == 0) {
      heartbeat_t hb;
      if (!decode(e, hb)) {
        ++st.undecodable;
        continue;
      }
      auto& h = health[hb.process.empty() ? e.channel.substr(hb_prefix.size()) : hb.process];
      h.process = hb.process;
      ++h.heartbeats;
      h.last_seen = e.time;
      h.state = hb.state;
      h.status = hb.status;
      h.received = hb.received;
      h.rejected = hb.rejected;
      h.stale = hb.stale;
      h.published = hb.published;
      if (hb.state > h.worst_state) {
        h.worst_state = hb.state;
        h.worst_at = e.time;
        h.worst_status = hb.status;
      }
      h.counters.clear();
      h.ticks_run = -1;
      h.ticks_missed = 0;
      for (int k = 0; k < hb.n_counters && k < static_cast<int>(hb.counter_names.size()); ++k) {
        const std::string& name = hb.counter_names[static_cast<std::size_t>(k)];
        const std::int64_t v = hb.counter_values[static_cast<std::size_t>(k)];
        if (name == "ticks.run") {
          h.ticks_run = v;
          continue;  // shown as the missed fraction, not as a counter
        }
        if (name == "ticks.missed") h.ticks_missed = v;
        if (v != 0) h.counters[name] = v;
      }
    } else if (st.type == "?" || !db.decode(e.data.data(), e.data.size(), dec)) {
      ++st.undecodable;
    }
  }
  for (auto& [ch, st] : stats) {
    auto& t = times[ch];
    std::sort(t.begin(), t.end());
    if (t.size() >= 2) {
      st.rate_hz = static_cast<double>(t.size() - 1) / to_seconds(t.back() - t.front());
      std::vector<TimeUs> d;
      for (std::size_t k = 1; k < t.size(); ++k) d.push_back(t[k] - t[k - 1]);
      std::vector<TimeUs> sorted = d;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                       sorted.end());
      st.median_period = sorted[sorted.size() / 2];
      const TimeUs limit = std::max<TimeUs>(3 * st.median_period, 200'000);
      for (std::size_t k = 0; k < d.size(); ++k) {
        if (d[k] > st.max_gap) {
          st.max_gap = d[k];
          st.max_gap_at = t[k];
        }
        if (d[k] > limit) ++st.gaps;
      }
    }
    s.channels.push_back(st);
  }
  for (auto& [name, h] : health) s.processes.push_back(h);
  s.attention = attention(s);
  return s;
}

std::string format_summary(const LogSummary& s) {
  std::ostringstream os;
  char buf[512];
  std::snprintf(buf, sizeof buf, "%lld events over %.3f s\n\n", static_cast<long long>(s.events),
                to_seconds(s.end - s.start));
  os << buf;
  if (s.attention.empty())
    os << "attention: nothing (no process missed more than 1 % of its ticks, none was DEGRADED "
          "or FAULT, no drops or rejections, every message decodes, no real time refused)\n\n";
  for (const auto& a : s.attention) os << "ATTENTION: " << a << "\n";
  if (!s.attention.empty()) os << "\n";
  std::size_t w = 7;
  for (const auto& c : s.channels) w = std::max(w, c.channel.size());
  std::snprintf(buf, sizeof buf, "%-*s  %-22s %8s %9s %10s %12s %5s %s\n", static_cast<int>(w),
                "channel", "type", "count", "rate_hz", "period_ms", "max_gap_ms@s", "gaps", "bad");
  os << buf;
  for (const auto& c : s.channels) {
    char gap[64];
    std::snprintf(gap, sizeof gap, "%.1f@%.1f", to_seconds(c.max_gap) * 1e3,
                  to_seconds(c.max_gap_at - s.start));
    std::snprintf(buf, sizeof buf, "%-*s  %-22s %8lld %9.2f %10.1f %12s %5lld %lld\n",
                  static_cast<int>(w), c.channel.c_str(), c.type.c_str(),
                  static_cast<long long>(c.count), c.rate_hz, to_seconds(c.median_period) * 1e3,
                  gap, static_cast<long long>(c.gaps), static_cast<long long>(c.undecodable));
    os << buf;
  }
  if (!s.processes.empty()) {
    os << "\nprocesses (last heartbeat)\n";
    std::snprintf(buf, sizeof buf, "%-16s %4s %-9s %-9s %7s %10s %9s %7s %10s  %s\n", "process",
                  "hb", "state", "worst", "missed", "received", "rejected", "stale", "published",
                  "status");
    os << buf;
    for (const auto& p : s.processes) {
      const double f = p.missed_fraction();
      char missed[32];
      if (f < 0)
        std::snprintf(missed, sizeof missed, "?");
      else
        std::snprintf(missed, sizeof missed, "%.1f%%", 100.0 * f);
      std::snprintf(buf, sizeof buf, "%-16s %4lld %-9s %-9s %7s %10lld %9lld %7lld %10lld  %s\n",
                    p.process.c_str(), static_cast<long long>(p.heartbeats), state_name(p.state),
                    state_name(p.worst_state), missed, static_cast<long long>(p.received),
                    static_cast<long long>(p.rejected), static_cast<long long>(p.stale),
                    static_cast<long long>(p.published), p.status.c_str());
      os << buf;
      for (const auto& [k, v] : p.counters) os << "    " << k << " = " << v << "\n";
    }
  }
  os << "\ncolumns: count = messages; rate_hz = (count - 1) / time from first to last; "
        "period_ms = median interval;\n"
        "  max_gap_ms@s = largest interval and when it began (s from the start); gaps = "
        "intervals longer than\n"
        "  max(3 x period, 200 ms); bad = messages that do not decode as their type.\n";
  if (!s.processes.empty())
    os << "  processes, from their heartbeats (TILLER_HEARTBEAT_<NAME>, 1 Hz): hb = heartbeats "
          "seen; state = in the\n"
          "  last one, worst = worst in any (ok, DEGRADED: running but an input is stale or a "
          "device missing,\n"
          "  FAULT: outputs neutral); missed = ticks.missed / (ticks.run + ticks.missed), ? when "
          "the log does not\n"
          "  count ticks run; received, rejected (dropped: malformed, non-finite, out of range), "
          "stale (times an input\n"
          "  went stale), published: totals since the process started; then its non-zero "
          "counters.\n";
  return os.str();
}

}  // namespace tiller::logtools
