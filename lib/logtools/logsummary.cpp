#include "logtools/logsummary.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include <tiller/heartbeat_t.hpp>

#include "logtools/lcm_schema.hpp"
#include "runtime/channels.hpp"

namespace tiller::logtools {

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
      h.counters.clear();
      for (int k = 0; k < hb.n_counters && k < static_cast<int>(hb.counter_names.size()); ++k) {
        if (hb.counter_values[static_cast<std::size_t>(k)] != 0)
          h.counters[hb.counter_names[static_cast<std::size_t>(k)]] =
              hb.counter_values[static_cast<std::size_t>(k)];
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
  return s;
}

std::string format_summary(const LogSummary& s) {
  std::ostringstream os;
  char buf[512];
  std::snprintf(buf, sizeof buf, "%lld events over %.3f s\n\n", static_cast<long long>(s.events),
                to_seconds(s.end - s.start));
  os << buf;
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
    std::snprintf(buf, sizeof buf, "%-16s %4s %-9s %10s %9s %7s %10s  %s\n", "process", "hb",
                  "state", "received", "rejected", "stale", "published", "status");
    os << buf;
    for (const auto& p : s.processes) {
      const char* st = p.state == heartbeat_t::STATE_OK         ? "ok"
                       : p.state == heartbeat_t::STATE_DEGRADED ? "degraded"
                                                                : "FAULT";
      std::snprintf(buf, sizeof buf, "%-16s %4lld %-9s %10lld %9lld %7lld %10lld  %s\n",
                    p.process.c_str(), static_cast<long long>(p.heartbeats), st,
                    static_cast<long long>(p.received), static_cast<long long>(p.rejected),
                    static_cast<long long>(p.stale), static_cast<long long>(p.published),
                    p.status.c_str());
      os << buf;
      for (const auto& [k, v] : p.counters) os << "    " << k << " = " << v << "\n";
    }
  }
  return os.str();
}

}  // namespace tiller::logtools
