// tiller-log: looks inside an LCM log.
//   tiller-log summary LOG                      channels, types, counts, rates, gaps; per process
//                                               its last heartbeat and non-zero drop counters
//   tiller-log csv LOG CHANNEL [--fields F,..] [--output FILE]
//                                               one CSV row per message, fields decoded by name
//   tiller-log fields LOG CHANNEL               the field paths of a channel's first message
//   tiller-log wait CHANNEL FIELD VALUE [--hold-s S] [--timeout-s S] [--mission FILE]
//                                               live: exits 0 once FIELD of CHANNEL has equalled
//                                               VALUE for S seconds, 1 after the timeout (a
//                                               launch file's ends_with process: "mission done")
#include <lcm/lcm-cpp.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>

#include "logtools/csv.hpp"
#include "logtools/lcm_schema.hpp"
#include "logtools/log_io.hpp"
#include "logtools/logsummary.hpp"
#include "mission/mission.hpp"
#include "runtime/app.hpp"
#include "runtime/live.hpp"
#include "runtime/log.hpp"

using namespace tiller;

namespace {
std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}
// Live wait for a field value on a channel (see the header). Prints the channel's
// distance_to_goal / segment fields (when it has them) every 10 s so a person sees progress.
int wait_for(const app::Args& a) {
  const auto& p = a.positional;
  const std::string channel = p[1], field = p[2], want = p[3];
  double hold_s = 0.0, timeout_s = 600.0;
  if (!a.get("mission").empty()) {
    const auto m = mission::load_mission_file(a.get("mission"));
    hold_s = m.station_keep_s;
    timeout_s = m.time_limit_s;
  }
  constexpr double kDay = 86400;
  if (!a.get("hold-s").empty())
    hold_s = app::number_option(a, "hold-s", 0, kDay, "a number of seconds from 0 to 86400");
  if (!a.get("timeout-s").empty())
    timeout_s = app::number_option(a, "timeout-s", 0, kDay, "a number of seconds from 0 to 86400");
  lcm::LCM lc(with_default_ttl(a.lcm_url));
  if (!lc.good()) throw std::runtime_error("cannot open LCM at " + a.lcm_url);
  const auto& db = logtools::tiller_types();
  logtools::Decoded last;
  bool have = false;
  std::optional<TimeUs> met_since;
  std::int64_t messages = 0;
  // Signed messages are checked with the key given (--key-file / TILLER_KEY_FILE) and their
  // trailer stripped; refused ones are ignored, like an undecodable one.
  auth::Verifier verifier(a.auth);
  std::function<void(const lcm::ReceiveBuffer*)> on_message = [&](const lcm::ReceiveBuffer* rb) {
    logtools::Decoded d;
    const auto* bytes = static_cast<const std::uint8_t*>(rb->data);
    const auto c = verifier.check(channel, bytes, static_cast<int>(rb->data_size), wall_time_us());
    if (!auth::accepted(c.verdict)) return;
    if (!db.decode(bytes, static_cast<std::size_t>(c.payload_size), d)) return;
    ++messages;
    const logtools::FieldValue* f = d.find(field);
    const bool met = f && f->to_string() == want;
    if (met && !met_since) met_since = wall_time_us();
    if (!met) met_since.reset();
    last = std::move(d);
    have = true;
  };
  struct Handler {
    std::function<void(const lcm::ReceiveBuffer*)>* f;
    void on(const lcm::ReceiveBuffer* rb, const std::string&) { (*f)(rb); }
  } handler{&on_message};
  lc.subscribe(channel, &Handler::on, &handler);
  const TimeUs t0 = wall_time_us();
  TimeUs next_note = t0 + 10 * kUsPerSecond;
  std::printf(
      "tiller-log: waiting for %s.%s == %s%s (time limit %.0f s)\n", channel.c_str(), field.c_str(),
      want.c_str(),
      hold_s > 0 ? (", then " + std::to_string(static_cast<int>(hold_s)) + " s more").c_str() : "",
      timeout_s);
  std::fflush(stdout);
  for (;;) {
    lc.handleTimeout(100);
    const TimeUs now = wall_time_us();
    if (met_since && to_seconds(now - *met_since) >= hold_s) {
      std::printf("tiller-log: %s.%s == %s after %.1f s (held %.1f s)\n", channel.c_str(),
                  field.c_str(), want.c_str(), to_seconds(*met_since - t0),
                  to_seconds(now - *met_since));
      return 0;
    }
    if (to_seconds(now - t0) >= timeout_s) {
      std::printf("tiller-log: FAILED: %s.%s never == %s for %.0f s within %.0f s (%lld messages",
                  channel.c_str(), field.c_str(), want.c_str(), hold_s, timeout_s,
                  static_cast<long long>(messages));
      if (have) {
        const auto* v = last.find(field);
        std::printf("; last %s = %s", field.c_str(), v ? v->to_string().c_str() : "(absent)");
      }
      std::printf(")\n");
      return 1;
    }
    if (now >= next_note) {
      next_note = now + 10 * kUsPerSecond;
      std::printf("tiller-log: %.0f s:", to_seconds(now - t0));
      if (!have) std::printf(" nothing on %s yet", channel.c_str());
      for (const char* k :
           {"segment", "n_waypoints", "distance_to_goal", "cross_track_error", field.c_str()}) {
        if (const auto* v = have ? last.find(k) : nullptr)
          std::printf(" %s=%.6g", k, v->is_text ? 0.0 : v->number);
      }
      std::printf("\n");
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  return app::guarded_main("tiller-log", [&] {
    const app::Spec spec{
        "tiller-log",
        "Summarises an LCM log or exports channels to CSV.\n"
        "Usage: tiller-log summary LOG | csv LOG CHANNEL [--fields F,..] [--output FILE] | fields "
        "LOG CHANNEL\n"
        "       tiller-log wait CHANNEL FIELD VALUE [--hold-s S] [--timeout-s S] [--mission FILE]",
        "",
        {{"fields", "F[,F..]", "fields to export (path or prefix: position, command, waypoints[0])",
          ""},
         {"output", "FILE", "write the CSV here instead of standard output", ""},
         {"hold-s", "S",
          "wait: the value must hold this long (default: the mission's station_keep_s, else 0)",
          ""},
         {"timeout-s", "S",
          "wait: give up (exit 1) after this long (default: the mission's time_limit_s, else 600)",
          ""},
         {"mission", "FILE", "wait: take hold and timeout from this mission file", ""}},
        false};  // no config file: --config refused (--lcm-url is for wait)
    const app::Args a = app::parse(argc, argv, spec);
    const auto& p = a.positional;
    if (p.size() == 4 && p[0] == "wait") return wait_for(a);
    if (p.size() == 2 && p[0] == "summary") {
      const auto summary = logtools::summarize(logtools::read_any_log(p[1]));
      std::cout << p[1] << ": " << logtools::format_summary(summary);
      return 0;
    }
    if (p.size() == 3 && (p[0] == "csv" || p[0] == "fields")) {
      const auto all = logtools::read_any_log(p[1]);
      const auto events = logtools::read_any_log(p[1], p[2]);
      if (events.empty()) {
        std::cerr << "tiller-log: no messages on channel " << p[2] << " in " << p[1] << "\n";
        return 1;
      }
      if (p[0] == "fields") {
        logtools::Decoded d;
        if (!logtools::tiller_types().decode(events[0].data.data(), events[0].data.size(), d)) {
          std::cerr << "tiller-log: " << p[2] << " does not carry a Tiller type\n";
          return 1;
        }
        std::cout << p[2] << ": " << d.type->name << "\n";
        for (const auto& f : d.fields)
          std::cout << "  " << f.path << " = " << f.to_string() << "\n";
        return 0;
      }
      // Every --fields name must choose something; else list what there is.
      const auto wanted = split_list(a.get("fields"));
      if (!wanted.empty()) {
        std::vector<std::string> paths;
        std::set<std::string> seen;
        logtools::Decoded d;
        std::string type;
        for (const auto& e : events) {
          if (!logtools::tiller_types().decode(e.data.data(), e.data.size(), d)) continue;
          type = d.type->name;
          for (const auto& f : d.fields)
            if (seen.insert(f.path).second) paths.push_back(f.path);
        }
        for (const auto& w : wanted) {
          bool any = false;
          for (const auto& path : paths) any = any || logtools::field_selected(path, {w});
          if (any) continue;
          std::string list;
          for (const auto& path : paths) list += (list.empty() ? "" : ", ") + path;
          std::cerr << "tiller-log: --fields: no field \"" << w << "\" in " << p[2]
                    << (type.empty() ? "" : " (" + type + ")") << "; its fields: " << list << "\n";
          return 2;
        }
      }
      std::size_t skipped = 0;
      std::size_t rows = 0;
      const TimeUs t0 = all.front().time;
      if (a.get("output").empty()) {
        rows =
            logtools::write_csv(std::cout, events, p[2], split_list(a.get("fields")), t0, &skipped);
      } else {
        std::ofstream out(a.get("output"));
        if (!out) throw std::runtime_error("cannot write " + a.get("output"));
        rows = logtools::write_csv(out, events, p[2], split_list(a.get("fields")), t0, &skipped);
        std::cerr << "tiller-log: " << rows << " rows to " << a.get("output") << "\n";
      }
      if (skipped)
        std::cerr << "tiller-log: " << skipped << " messages did not decode and were skipped\n";
      return rows > 0 ? 0 : 1;
    }
    std::cerr << "tiller-log: expected: summary LOG | csv LOG CHANNEL | fields LOG CHANNEL (see "
                 "--help)\n";
    return 2;
  });
}
